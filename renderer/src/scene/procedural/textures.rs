//! Procedural RGBA8 textures for the built-in scene, deterministic (no random state): stone
//! floor tiles, an iron grille and a leaf canopy whose alpha channels are cut-outs. UVs are in
//! world units and the sampler repeats, so one image covers one metre.

use crate::scene::Image;

/// A stable hash of integer coordinates to `[0, 1)`.
fn hash(x: u32, y: u32, salt: u32) -> f32 {
    let mut h = x
        .wrapping_mul(0x8da6_b343)
        .wrapping_add(y.wrapping_mul(0xd816_3841))
        .wrapping_add(salt.wrapping_mul(0xcb1a_b31f));
    h ^= h >> 13;
    h = h.wrapping_mul(0x5bd1_e995);
    h ^= h >> 15;
    (h & 0xffff) as f32 / 65536.0
}

fn image(size: u32, texel: impl Fn(u32, u32) -> [u8; 4]) -> Image {
    let mut rgba8 = Vec::with_capacity((size * size * 4) as usize);
    for y in 0..size {
        for x in 0..size {
            rgba8.extend(texel(x, y));
        }
    }
    Image {
        width: size,
        height: size,
        rgba8,
    }
}

fn srgb(linear: f32) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

/// 2×2 stone tiles per image, each a slightly different warm grey, with dark grout lines.
pub fn stone_tiles() -> Image {
    const SIZE: u32 = 128;
    let tile = SIZE / 2;
    image(SIZE, |x, y| {
        let (tx, ty) = (x / tile, y / tile);
        let (lx, ly) = (x % tile, y % tile);
        let grout = lx < 2 || ly < 2;
        let shade = 0.28 + 0.12 * hash(tx, ty, 1) + 0.03 * hash(x, y, 2);
        let c = if grout { 0.06 } else { shade };
        [srgb(c * 1.05), srgb(c), srgb(c * 0.9), 255]
    })
}

/// A square iron grille: bars 1/8 of the cell wide, transparent holes between.
pub fn grille() -> Image {
    const SIZE: u32 = 64;
    let cell = SIZE / 4;
    image(SIZE, |x, y| {
        let bar = x % cell < 2 || y % cell < 2;
        let c = srgb(0.05);
        [c, c, c, if bar { 255 } else { 0 }]
    })
}

/// A canopy of leaves: overlapping discs of varied greens on a transparent ground.
pub fn leaves() -> Image {
    const SIZE: u32 = 128;
    const CELL: u32 = 16;
    image(SIZE, |x, y| {
        let (cx, cy) = (x / CELL, y / CELL);
        // The nearest leaf centre among this cell's and its neighbours' (wrapping).
        let mut best: Option<(f32, u32, u32)> = None;
        for dy in [SIZE / CELL - 1, 0, 1] {
            for dx in [SIZE / CELL - 1, 0, 1] {
                let (nx, ny) = ((cx + dx) % (SIZE / CELL), (cy + dy) % (SIZE / CELL));
                let px = (nx as f32 + hash(nx, ny, 3)) * CELL as f32;
                let py = (ny as f32 + hash(nx, ny, 4)) * CELL as f32;
                let wrap = |d: f32| {
                    let d = d.abs();
                    d.min(SIZE as f32 - d)
                };
                let d = wrap(x as f32 - px).hypot(wrap(y as f32 - py));
                if best.is_none_or(|b| d < b.0) {
                    best = Some((d, nx, ny));
                }
            }
        }
        #[expect(clippy::expect_used, reason = "the loop above visits nine cells")]
        let (d, nx, ny) = best.expect("nine candidates");
        let radius = CELL as f32 * (0.55 + 0.35 * hash(nx, ny, 5));
        let g = 0.08 + 0.12 * hash(nx, ny, 6);
        [
            srgb(g * 0.45),
            srgb(g),
            srgb(g * 0.3),
            if d < radius { 255 } else { 0 },
        ]
    })
}
