//! Labels on the shadow-atlas view: each light's light id and region side, written at its first
//! region, where the view draws the atlas (square, letterboxed in the frame).

use anyhow::Result;
use plotters::prelude::*;
use renderer::shadow::ShadowReport;
use renderer::shadow::frame::DIRECTIONAL_ID;

use crate::bench::charts::{FONT, register_font};

/// Regions drawn smaller than this (pixels) get no label.
const MIN_LABELLED: f32 = 20.0;

/// Writes the labels of `report`'s regions over the `w`×`h` RGBA image `rgba` of the atlas
/// view of an `atlas`-texel atlas. Without a font it leaves the image alone and says why.
pub fn label(rgba: &mut [u8], (w, h): (u32, u32), atlas: u32, report: &ShadowReport) -> Result<()> {
    register_font()?;
    let side = w.min(h) as f32;
    let origin = ((w as f32 - side) / 2.0, (h as f32 - side) / 2.0);
    let scale = side / atlas.max(1) as f32;
    let mut rgb: Vec<u8> = rgba.chunks(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        for (key, rect) in report.regions.iter().filter(|(k, _)| k.face == 0) {
            let drawn = rect.side as f32 * scale;
            if drawn < MIN_LABELLED {
                continue;
            }
            let name = if key.light >= DIRECTIONAL_ID {
                format!("sun{} {}", key.light - DIRECTIONAL_ID, rect.side)
            } else {
                format!("L{} {}", key.light, rect.side)
            };
            let size = (drawn / 5.0).clamp(9.0, 16.0) as u32;
            let at = (
                (origin.0 + rect.x as f32 * scale + 3.0) as i32,
                (origin.1 + rect.y as f32 * scale + 3.0) as i32,
            );
            root.draw_text(&name, &(FONT, size).into_font().color(&YELLOW), at)?;
        }
        root.present()?;
    }
    for (px, c) in rgba.chunks_mut(4).zip(rgb.chunks(3)) {
        px[..3].copy_from_slice(c);
    }
    Ok(())
}
