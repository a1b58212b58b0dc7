//! The built-in decal materials, made in code so that the demo and tests need no files: a
//! scorch mark, a wet stain and a painted sign (with a normal map for its raised paint).

use glam::{Vec2, Vec3};

use super::{DecalImage, DecalMaterial};

/// Side of every built-in material's images, in texels.
pub const SIDE: u32 = 128;

/// The built-in materials: `scorch`, `stain` and `sign`, in that order.
pub fn materials() -> Vec<DecalMaterial> {
    vec![scorch(), stain(), sign()]
}

/// Value noise in 0..1 (smoothly interpolated hashed lattice), for ragged edges.
fn noise(p: Vec2) -> f32 {
    let hash = |x: i32, y: i32| {
        let mut h = (x as u32).wrapping_mul(0x8da6_b343) ^ (y as u32).wrapping_mul(0xd816_3841);
        h = (h ^ (h >> 13)).wrapping_mul(0x85eb_ca6b);
        (h ^ (h >> 16)) as f32 / u32::MAX as f32
    };
    let (i, f) = (p.floor(), p - p.floor());
    let s = f * f * (Vec2::splat(3.0) - 2.0 * f);
    let (x, y) = (i.x as i32, i.y as i32);
    let top = hash(x, y) + (hash(x + 1, y) - hash(x, y)) * s.x;
    let bottom = hash(x, y + 1) + (hash(x + 1, y + 1) - hash(x, y + 1)) * s.x;
    top + (bottom - top) * s.y
}

/// Two octaves of [`noise`].
fn fbm(p: Vec2) -> f32 {
    0.65 * noise(p) + 0.35 * noise(p * 2.3 + 7.1)
}

/// Texel centre `(x, y)` in `[−1, 1]²`, +Y up.
fn centred(x: u32, y: u32) -> Vec2 {
    let s = SIDE as f32;
    Vec2::new(
        (x as f32 + 0.5) / s * 2.0 - 1.0,
        1.0 - (y as f32 + 0.5) / s * 2.0,
    )
}

fn byte(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// A soft black scorch mark with a ragged rim; rough and matte.
fn scorch() -> DecalMaterial {
    let coverage = |x, y| {
        let p = centred(x, y);
        let ragged = p.length() + 0.35 * (fbm(p * 4.0) - 0.5);
        1.0 - smoothstep(0.45, 0.95, ragged)
    };
    DecalMaterial {
        name: "scorch".into(),
        base_color: DecalImage::from_fn(SIDE, SIDE, |x, y| {
            let a = coverage(x, y);
            let soot = 0.02 + 0.06 * fbm(centred(x, y) * 9.0);
            [
                byte(soot),
                byte(soot * 0.9),
                byte(soot * 0.8),
                byte(a * 0.95),
            ]
        }),
        normal: None,
        orm: Some(DecalImage::solid(SIDE, SIDE, [255, 242, 0, 255])),
        emissive: None,
    }
}

/// A brown water stain, darker at its rim, glossy (low roughness) where wet.
fn stain() -> DecalMaterial {
    let blob = |x, y| {
        let p = centred(x, y) * 1.15;
        p.length() + 0.45 * (fbm(p * 2.5 + 3.0) - 0.5)
    };
    DecalMaterial {
        name: "stain".into(),
        base_color: DecalImage::from_fn(SIDE, SIDE, |x, y| {
            let d = blob(x, y);
            let a = 1.0 - smoothstep(0.55, 0.75, d);
            let rim = smoothstep(0.35, 0.7, d);
            let c = Vec3::new(0.32, 0.22, 0.12) * (1.0 - 0.45 * rim);
            [byte(c.x), byte(c.y), byte(c.z), byte(a * 0.8)]
        }),
        normal: None,
        orm: Some(DecalImage::from_fn(SIDE, SIDE, |x, y| {
            let wet = 1.0 - smoothstep(0.3, 0.7, blob(x, y));
            [255, byte(0.8 - 0.6 * wet), 0, 255]
        })),
        emissive: None,
    }
}

/// The sign's black ink: a ring inside the disc's rim and an upward arrow (0..1 coverage).
fn ink(p: Vec2) -> f32 {
    let ring = smoothstep(0.64, 0.68, p.length());
    let shaft =
        (1.0 - smoothstep(0.08, 0.11, p.x.abs())) * (1.0 - smoothstep(0.35, 0.38, p.y.abs() + 0.1));
    let head = (1.0 - smoothstep(0.0, 0.03, p.x.abs() + p.y - 0.45)) * smoothstep(0.17, 0.2, p.y);
    ring.max(shaft).max(head)
}

/// The sign's yellow disc (0..1 coverage).
fn disc(p: Vec2) -> f32 {
    1.0 - smoothstep(0.78, 0.82, p.length())
}

/// A painted warning sign: a yellow disc with a black ring and arrow, the paint slightly raised
/// (its edges in the normal map: the ink is a second coat) and glossier than most surfaces.
fn sign() -> DecalMaterial {
    let height = |p: Vec2| disc(p) * (1.0 + 0.5 * ink(p));
    let step = 2.0 / SIDE as f32;
    DecalMaterial {
        name: "sign".into(),
        base_color: DecalImage::from_fn(SIDE, SIDE, |x, y| {
            let p = centred(x, y);
            let c = Vec3::new(0.95, 0.72, 0.05).lerp(Vec3::splat(0.03), ink(p));
            [byte(c.x), byte(c.y), byte(c.z), byte(disc(p))]
        }),
        normal: Some(DecalImage::from_fn(SIDE, SIDE, |x, y| {
            let p = centred(x, y);
            let dx = (height(p + Vec2::X * step) - height(p - Vec2::X * step)) / (2.0 * step);
            let dy = (height(p + Vec2::Y * step) - height(p - Vec2::Y * step)) / (2.0 * step);
            let n = Vec3::new(-dx * 0.01, -dy * 0.01, 1.0).normalize();
            [
                byte(n.x * 0.5 + 0.5),
                byte(n.y * 0.5 + 0.5),
                byte(n.z * 0.5 + 0.5),
                255,
            ]
        })),
        orm: Some(DecalImage::solid(SIDE, SIDE, [255, 90, 0, 255])),
        emissive: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decals::{Channel, DecalAtlas, DecalAtlasConfig};

    #[test]
    fn built_ins_are_valid_and_pack_into_one_small_atlas() {
        let m = materials();
        assert_eq!(
            m.iter().map(|m| m.name.as_str()).collect::<Vec<_>>(),
            ["scorch", "stain", "sign"]
        );
        let atlas = DecalAtlas::build(&m, DecalAtlasConfig::default()).unwrap();
        assert!(atlas.size <= 512, "{}", atlas.size);
        assert_ne!(atlas.entries[2].channels & (1 << Channel::Normal as u32), 0);
    }

    #[test]
    fn built_ins_are_opaque_inside_and_clear_at_their_corners() {
        for m in materials() {
            let alpha = |x: u32, y: u32| m.base_color.rgba[((y * SIDE + x) * 4 + 3) as usize];
            assert!(alpha(SIDE / 2, SIDE / 2) > 150, "{} centre", m.name);
            assert_eq!(alpha(0, 0), 0, "{} corner", m.name);
        }
    }
}
