//! The built-in particle textures, made in code: one layer per [`ParticleTexture`] of a small
//! texture array (smoke, spark, dust), white with the shape in alpha, with mip levels so small
//! and distant particles do not shimmer.
//!
//! [`ParticleTexture`]: super::ParticleTexture

use super::random::pcg;

/// Side of each layer's top level, texels.
pub const SPRITE_SIDE: u32 = 64;
/// Layers: one per `ParticleTexture`, in its order.
pub const SPRITE_LAYERS: u32 = 3;

/// Mip levels of a layer (down to 1×1).
pub fn sprite_levels() -> u32 {
    SPRITE_SIDE.ilog2() + 1
}

/// Every layer's RGBA8 texels with all its mip levels, layer by layer (each layer's levels
/// from the largest down), as `wgpu`'s layer-major upload order wants them.
pub fn sprite_texels() -> Vec<u8> {
    let shapes: [fn(f32, f32) -> f32; 3] = [smoke_alpha, spark_alpha, dust_alpha];
    let mut out = Vec::new();
    for shape in shapes {
        let n = SPRITE_SIDE as usize;
        let mut level: Vec<f32> = (0..n * n)
            .map(|i| {
                let (x, y) = (i % n, i / n);
                let u = (x as f32 + 0.5) / n as f32 * 2.0 - 1.0;
                let v = (y as f32 + 0.5) / n as f32 * 2.0 - 1.0;
                shape(u, v).clamp(0.0, 1.0)
            })
            .collect();
        let mut side = n;
        loop {
            out.extend(
                level
                    .iter()
                    .flat_map(|&a| [255, 255, 255, (a * 255.0).round() as u8]),
            );
            if side == 1 {
                break;
            }
            level = halve(&level, side);
            side /= 2;
        }
    }
    out
}

/// The next mip level of a `side`×`side` level: the mean of each 2×2 block.
fn halve(level: &[f32], side: usize) -> Vec<f32> {
    let half = side / 2;
    (0..half * half)
        .map(|i| {
            let (x, y) = (2 * (i % half), 2 * (i / half));
            let at = |dx: usize, dy: usize| level[(y + dy) * side + x + dx];
            (at(0, 0) + at(1, 0) + at(0, 1) + at(1, 1)) * 0.25
        })
        .collect()
}

/// Value noise in [0, 1] on an 8×8 lattice over the sprite, smoothly interpolated.
fn value_noise(u: f32, v: f32) -> f32 {
    let (x, y) = ((u * 0.5 + 0.5) * 8.0, (v * 0.5 + 0.5) * 8.0);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let smooth = |t: f32| t * t * (3.0 - 2.0 * t);
    let corner = |dx: f32, dy: f32| {
        let h = pcg((x0 + dx) as u32 ^ pcg((y0 + dy) as u32 ^ 0x5EED));
        (h >> 8) as f32 / 16_777_216.0
    };
    let top = corner(0.0, 0.0) + (corner(1.0, 0.0) - corner(0.0, 0.0)) * smooth(fx);
    let bottom = corner(0.0, 1.0) + (corner(1.0, 1.0) - corner(0.0, 1.0)) * smooth(fx);
    top + (bottom - top) * smooth(fy)
}

/// A soft round puff broken up by noise, fading to nothing at its rim.
fn smoke_alpha(u: f32, v: f32) -> f32 {
    let r = (u * u + v * v).sqrt();
    let falloff = (1.0 - r).max(0.0).powf(1.5);
    falloff * (0.55 + 0.45 * value_noise(u, v)) * 1.4
}

/// A hot core with a fast glow around it.
fn spark_alpha(u: f32, v: f32) -> f32 {
    let r2 = u * u + v * v;
    (-r2 * 12.0).exp() * (1.0 - r2.sqrt()).max(0.0)
}

/// A small mote with a hard, slightly soft edge.
fn dust_alpha(u: f32, v: f32) -> f32 {
    let r = (u * u + v * v).sqrt();
    ((0.8 - r) / 0.15).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_layer_is_opaque_inside_and_clear_at_its_corners_at_every_level() {
        let texels = sprite_texels();
        let per_level: Vec<usize> = (0..sprite_levels())
            .map(|l| ((SPRITE_SIDE >> l) as usize).pow(2) * 4)
            .collect();
        let per_layer: usize = per_level.iter().sum();
        assert_eq!(texels.len(), per_layer * SPRITE_LAYERS as usize);
        for layer in 0..SPRITE_LAYERS as usize {
            let top = &texels[layer * per_layer..][..per_level[0]];
            let n = SPRITE_SIDE as usize;
            let alpha = |x: usize, y: usize| top[(y * n + x) * 4 + 3];
            assert_eq!(alpha(0, 0), 0, "layer {layer} corner");
            assert!(alpha(n / 2, n / 2) > 100, "layer {layer} centre");
            assert!(top.chunks(4).all(|t| t[..3] == [255, 255, 255]));
        }
        // The layers are different shapes.
        assert_ne!(texels[..per_level[0]], texels[per_layer..][..per_level[0]]);
    }
}
