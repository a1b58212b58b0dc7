//! A decal whose every channel is a different, asymmetric letter, and a CPU projection that says
//! where each letter must land: the decal image tests' independent reference.
//!
//! The material is 64 × 64 texels: base colour an "F" (red ink on blue paper, opaque), normal an
//! "R" (ink tilted 40° towards the image's +X, paper flat), occlusion-roughness-metalness a "4"
//! (ink occluded to 0.35, paper 1; roughness 0.8 and metalness 0 everywhere). A mirrored, rotated
//! or transposed projection moves each letter; channels read from each other's images put one
//! letter's effect in another's shape.
//!
//! The reference is written from the documented conventions, not from the shaders: the box is
//! `world_from_box` applied to the unit cube `[−0.5, 0.5]³`, the image's +X runs along box +X
//! and its top along box +Y. For each pixel it casts camera rays (built from the camera's eye,
//! target and field of view, not from the renderer's matrices or depth) onto the floor plane
//! y = 0, takes the box coordinates of the hit with the inverse of `world_from_box`, and so the
//! texel and the letter cell.

use glam::{Mat4, Quat, Vec3};
use renderer::decals::{Channel, Decal, DecalImage, DecalMaterial};
use renderer::frame::FrameCamera;
use renderer::scene::procedural::SceneBuilder;
use renderer::scene::{LightKind, Scene, SceneLight};

/// Frame size of the letter tests.
pub const WIDTH: u32 = 160;
pub const HEIGHT: u32 = 120;
/// Texels on a side of each channel's image, and of one glyph cell.
pub const SIDE: u32 = 64;
pub const CELL: u32 = SIDE / 8;

/// An 8 × 8 glyph, top row first; `#` is ink.
pub type Glyph = [&'static str; 8];

pub const F: Glyph = [
    "........", ".######.", ".##.....", ".##.....", ".#####..", ".##.....", ".##.....", "........",
];
pub const R: Glyph = [
    "........", ".#####..", ".##..##.", ".##..##.", ".#####..", ".##.##..", ".##..##.", "........",
];
pub const FOUR: Glyph = [
    "........", "....##..", "...###..", "..#.##..", ".#..##..", ".######.", "....##..", "........",
];

/// Whether texel `(x, y)` of a [`SIDE`]-texel image of `glyph` is ink.
pub fn ink(glyph: &Glyph, x: u32, y: u32) -> bool {
    glyph[(y / CELL) as usize].as_bytes()[(x / CELL) as usize] == b'#'
}

/// An image of `glyph`: `ink` texels where it is inked, `paper` elsewhere.
pub fn glyph_image(glyph: &Glyph, ink_texel: [u8; 4], paper: [u8; 4]) -> DecalImage {
    DecalImage::from_fn(
        SIDE,
        SIDE,
        |x, y| {
            if ink(glyph, x, y) { ink_texel } else { paper }
        },
    )
}

/// Base-colour ink and paper (sRGB, opaque), normal ink (40° towards +X) and paper (flat),
/// occlusion-roughness-metalness ink (occlusion 0.35) and paper.
pub const RED_INK: [u8; 4] = [230, 40, 30, 255];
pub const BLUE_PAPER: [u8; 4] = [40, 90, 230, 255];
pub const TILTED: [u8; 4] = [210, 128, 226, 255];
pub const FLAT: [u8; 4] = [128, 128, 255, 255];
pub const OCCLUDED: [u8; 4] = [89, 204, 0, 255];
pub const OPEN: [u8; 4] = [255, 204, 0, 255];

/// The letter material, with the letter of `erased` (if any) painted over in its paper: the
/// frame pairs that differ in one channel's letter only.
pub fn material(erased: Option<Channel>) -> DecalMaterial {
    let image = |channel, glyph: &Glyph, ink: [u8; 4], paper| {
        glyph_image(
            glyph,
            if erased == Some(channel) { paper } else { ink },
            paper,
        )
    };
    DecalMaterial {
        name: format!("letters, {erased:?} erased"),
        base_color: image(Channel::BaseColor, &F, RED_INK, BLUE_PAPER),
        normal: Some(image(Channel::Normal, &R, TILTED, FLAT)),
        orm: Some(image(Channel::Orm, &FOUR, OCCLUDED, OPEN)),
        emissive: None,
    }
}

/// A grey floor, 10 × 10 around the origin at y = 0.
pub fn scene() -> Scene {
    let mut b = SceneBuilder::new();
    let floor = b.material("floor", Vec3::splat(0.6), 0.9);
    b.cuboid(Vec3::new(-5.0, 0.0, -5.0), Vec3::new(5.0, 0.0, 5.0), floor);
    b.build()
}

/// Camera: eye, target and vertical field of view (degrees).
pub const EYE: Vec3 = Vec3::new(0.8, 4.2, 3.0);
pub const TARGET: Vec3 = Vec3::new(0.0, 0.0, 0.1);
pub const FOV_DEGREES: f32 = 50.0;

pub fn camera() -> FrameCamera {
    let aspect = WIDTH as f32 / HEIGHT as f32;
    FrameCamera::look_at(
        EYE,
        TARGET,
        Vec3::Y,
        FOV_DEGREES.to_radians(),
        aspect,
        (0.1, 50.0),
    )
}

/// The decal: a 2.6 × 2.2 box (0.8 deep) on the floor at the origin, turned 30° about the
/// vertical and its projection axis tilted 15° off it, so that the image lands sheared.
pub fn decal_box() -> Mat4 {
    let turn = Quat::from_rotation_y(30f32.to_radians());
    let lay_flat = Quat::from_rotation_x(-90f32.to_radians());
    let tilt = Quat::from_rotation_x(15f32.to_radians());
    Mat4::from_scale_rotation_translation(
        Vec3::new(2.6, 2.2, 0.8),
        turn * lay_flat * tilt,
        Vec3::new(0.0, 0.0, 0.05),
    )
}

pub fn decal() -> Decal {
    Decal::new(decal_box(), 0)
}

/// A directional light from the box's +X side, 20° above the floor: a letter of normals tilted
/// towards +X faces it more squarely than the flat paper.
pub fn grazing_light() -> SceneLight {
    let along = decal_box().x_axis.truncate();
    let along = Vec3::new(along.x, 0.0, along.z).normalize();
    let (s, c) = 20f32.to_radians().sin_cos();
    SceneLight {
        kind: LightKind::Directional,
        position: Vec3::ZERO,
        direction: -(along * c + Vec3::Y * s),
        color: Vec3::ONE,
        intensity: 3.0,
        range: None,
        casts_shadow: false,
    }
}

/// Where the ray through image point `(x, y)` (pixels, top left origin) meets the floor.
fn floor_point(x: f32, y: f32) -> Option<Vec3> {
    let forward = (TARGET - EYE).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    let half = (FOV_DEGREES.to_radians() * 0.5).tan();
    let aspect = WIDTH as f32 / HEIGHT as f32;
    let sx = (x / WIDTH as f32 * 2.0 - 1.0) * half * aspect;
    let sy = (1.0 - y / HEIGHT as f32 * 2.0) * half;
    let direction = forward + right * sx + up * sy;
    let t = -EYE.y / direction.y;
    (t > 0.0).then(|| EYE + direction * t)
}

/// What a pixel's surroundings show of one channel's letter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coverage {
    /// Every probe lies on ink.
    Ink,
    /// Every probe lies on paper or outside the box.
    Clear,
    /// Mixed: the band along an edge, left unchecked.
    Band,
}

/// Texel coordinates of a floor point in the decal image (fractional; `None` outside the box).
pub fn texel_of(point: Vec3) -> Option<(f32, f32)> {
    let local = decal_box().inverse().transform_point3(point);
    let inside = local.abs().cmple(Vec3::splat(0.5)).all();
    inside.then_some(((local.x + 0.5) * SIDE as f32, (0.5 - local.y) * SIDE as f32))
}

/// Pixel `(x, y)` against `glyph` (`None`: the box itself, every texel ink). Probed at the
/// pixel's centre and the eight points one pixel away, each with the four texel positions half
/// a texel away (what bilinear filtering reads): the band left out is a pixel and half a texel
/// wide on either side of each edge.
pub fn coverage(glyph: Option<&Glyph>, x: u32, y: u32) -> Coverage {
    let (mut inked, mut clear) = (false, false);
    for dy in [-1.0, 0.0, 1.0] {
        for dx in [-1.0, 0.0, 1.0] {
            let Some(p) = floor_point(x as f32 + 0.5 + dx, y as f32 + 0.5 + dy) else {
                return Coverage::Band;
            };
            for (tx, ty) in [(-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5)] {
                let on_ink = texel_of(p).is_some_and(|(u, v)| {
                    let (u, v) = (u + tx, v + ty);
                    let within = (0.0..SIDE as f32).contains(&u) && (0.0..SIDE as f32).contains(&v);
                    within && glyph.is_none_or(|g| ink(g, u as u32, v as u32))
                });
                inked |= on_ink;
                clear |= !on_ink;
            }
        }
    }
    match (inked, clear) {
        (true, false) => Coverage::Ink,
        (false, true) => Coverage::Clear,
        _ => Coverage::Band,
    }
}
