//! What `cargo xtask render` and the demo write and print: PNG and text files, one-line
//! summaries of the shadow and particle passes, and the difference of two frames.

use std::path::Path;

use anyhow::{Context as _, Result};

/// Per-channel 8-bit differences of two RGBA8 images: mean and 99th percentile.
pub fn difference(a: &[u8], b: &[u8]) -> (f64, u8) {
    let mut d: Vec<u8> = a
        .chunks(4)
        .zip(b.chunks(4))
        .flat_map(|(p, q)| (0..3).map(move |c| p[c].abs_diff(q[c])))
        .collect();
    let mean = d.iter().map(|&x| f64::from(x)).sum::<f64>() / d.len().max(1) as f64;
    d.sort_unstable();
    (mean, d.get(d.len() * 99 / 100).copied().unwrap_or(0))
}

/// Writes an RGBA8 image, creating its folder.
pub fn save_png(out: &Path, rgba: &[u8], (w, h): (u32, u32)) -> Result<()> {
    if let Some(dir) = out.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    image::save_buffer(out, rgba, w, h, image::ExtendedColorType::Rgba8)
        .with_context(|| format!("writing {}", out.display()))
}

/// Writes a text file, creating its folder.
pub fn save_text(out: &Path, text: &str) -> Result<()> {
    if let Some(dir) = out.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    std::fs::write(out, text).with_context(|| format!("writing {}", out.display()))
}

/// One line on what the shadow pass did.
pub fn shadow_summary(r: &renderer::shadow::ShadowReport) -> String {
    let histogram: Vec<String> = r
        .resolution_histogram
        .iter()
        .map(|(side, n)| format!("{n}×{side}²"))
        .collect();
    let c = r.cache;
    format!(
        "shadows: {} of {} lights shadowed (regions {}), {} degraded, {} evicted{}; regions: {} redrawn, {} copied, {} untouched; {} caster draws",
        r.shadowed,
        r.requested,
        if histogram.is_empty() {
            "none".into()
        } else {
            histogram.join(" ")
        },
        r.degraded.len(),
        r.evicted.len(),
        if r.repacked { ", atlas repacked" } else { "" },
        c.redrawn,
        c.copied,
        c.untouched,
        c.draws,
    )
}

/// One line on the frame's particles.
pub fn particle_summary(p: &renderer::frame::ParticleReport) -> String {
    format!(
        "particles: {} alive, {} visible, {} births refused (pool full); lighting atlas: {} texels lit{}",
        p.alive,
        p.visible,
        p.starved,
        p.atlas_cells * 4,
        if p.atlas_shrink > 0 {
            format!(
                ", regions shrunk by {} size class(es) to fit",
                p.atlas_shrink
            )
        } else {
            String::new()
        }
    )
}

/// The frame's scene draws in one line: how many, in how many batches, and what culling kept.
pub fn draws_line(d: &renderer::frame_data::SceneDrawReport) -> String {
    let culling = if d.occlusion {
        "GPU frustum and occlusion culling"
    } else {
        "GPU frustum culling"
    };
    let kept = d.visible.map_or_else(
        || "culling off".to_string(),
        |v| format!("{v} drawn after {culling}"),
    );
    format!(
        "draws: {} opaque and masked in {} batches ({kept}), {} blended",
        d.draws, d.batches, d.blended
    )
}
