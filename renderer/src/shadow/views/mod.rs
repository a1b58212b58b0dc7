//! Light-space projections of the shadow atlas: one perspective view per spot light, six
//! guard-banded perspective faces per point light, four stable orthographic cascades for the
//! directional light, and the [`Frustum`] that casters are culled against for each of them.
//!
//! Conventions (shared with the GPU code that samples the atlas):
//! - right-handed world and view space, every view looks down its −Z;
//! - reversed Z: a view's near plane maps to depth 1, its far plane to 0 (clip `0 ≤ z ≤ w`);
//! - NDC `x, y ∈ [-1, 1]` cover the whole atlas region of the view, `+y` up;
//! - perspective views have a near plane at [`perspective_near`]`(range)`, small relative to
//!   the range; lights of infinite range must be given a finite range by the caller (clamped
//!   to the scene's extent) — a non-finite range falls back to an infinite far plane.
//!
//! Everything here is plain `f32` math on `glam` types: no GPU objects.
//!
//! Cube faces are in `cube`, directional cascades in `cascade`; both are re-exported here.

mod cascade;
mod cube;

#[cfg(test)]
mod cascade_tests;
#[cfg(test)]
mod tests;

#[cfg(any(test, feature = "internals"))]
pub use cascade::{CASCADE_COUNT, CASCADE_SPLIT_LAMBDA, cascade_splits, slice_bounding_sphere};
pub use cascade::{CameraLens, cascade_views};
pub use cube::cube_views;
#[cfg(any(test, feature = "internals"))]
pub use cube::{CUBE_FACE_DIRECTIONS, CUBE_FACE_UPS, cube_face, cube_tan_half_fov};

use glam::camera::rh::view::look_to_mat4;
use glam::{Mat4, Vec3, Vec4};

use crate::culling::Plane;
use crate::scene::Aabb;

/// Largest half angle a spot view covers; wider cones are clamped (a single perspective view
/// cannot reach 90°).
pub const MAX_SPOT_HALF_ANGLE: f32 = std::f32::consts::FRAC_PI_2 - 0.01;

/// One shadow map rendering: what the GPU needs and what casters are culled against.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightView {
    /// World → clip, reversed Z (near 1, far 0). x,y in [-1,1] map to the region.
    pub clip_from_world: Mat4,
    /// World size of one texel: at unit distance along the view axis for perspective views
    /// (multiply by the distance), or absolute for orthographic ones.
    pub texel_world: f32,
    /// Orthographic (directional cascade) rather than perspective (spot light, cube face).
    pub orthographic: bool,
    /// Directional cascades: the view depth (camera) where this cascade ends; 0 otherwise.
    pub split_far: f32,
}

impl LightView {
    /// NDC of world point `p`: `x, y` in the region's `[-1, 1]`, `z` the reversed-Z depth.
    /// Meaningless for points at or behind a perspective view's eye plane (`w ≤ 0`).
    pub fn ndc(&self, p: Vec3) -> Vec3 {
        let clip = self.clip_from_world * p.extend(1.0);
        clip.truncate() / clip.w
    }

    /// The frustum casters are culled against.
    pub fn frustum(&self) -> Frustum {
        Frustum::from_clip(self.clip_from_world)
    }
}

/// The six planes of a clip volume in world space, normals pointing inwards.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frustum {
    planes: [Plane; 6],
}

impl Frustum {
    /// The planes of `m` (any world → clip matrix) by Gribb/Hartmann, for the reversed-Z clip
    /// volume `-w ≤ x ≤ w`, `-w ≤ y ≤ w`, `0 ≤ z ≤ w`. Order: left, right, bottom, top, near
    /// (`z ≤ w`, depth 1), far (`z ≥ 0`, depth 0).
    pub fn from_clip(m: Mat4) -> Self {
        let (r0, r1, r2, r3) = (m.row(0), m.row(1), m.row(2), m.row(3));
        Self {
            planes: [
                plane(r3 + r0),
                plane(r3 - r0),
                plane(r3 + r1),
                plane(r3 - r1),
                plane(r3 - r2),
                plane(r2),
            ],
        }
    }

    /// The planes: left, right, bottom, top, near, far.
    pub fn planes(&self) -> &[Plane; 6] {
        &self.planes
    }

    /// Whether `b` may touch the volume. Conservative: `false` only when the box lies entirely
    /// outside one plane (a box near an edge or corner but outside may still answer `true`).
    /// An empty box never intersects.
    pub fn intersects_aabb(&self, b: &Aabb) -> bool {
        if b.is_empty() {
            return false;
        }
        self.planes.iter().all(|p| {
            // The corner furthest along the normal: if even it is outside, the box is.
            let corner = Vec3::select(p.normal.cmpge(Vec3::ZERO), b.max, b.min);
            p.distance(corner) >= 0.0
        })
    }

    /// Whether `p` is inside or on every plane.
    pub fn contains_point(&self, p: Vec3) -> bool {
        self.planes.iter().all(|plane| plane.distance(p) >= 0.0)
    }
}

/// The plane `v.xyz · p + v.w ≥ 0`, normalised. A degenerate row (zero normal) keeps its
/// unnormalised form, which keeps everything when `v.w ≥ 0` and nothing otherwise.
fn plane(v: Vec4) -> Plane {
    let len = v.truncate().length();
    let scale = if len > 0.0 { len.recip() } else { 1.0 };
    Plane {
        normal: v.truncate() * scale,
        d: v.w * scale,
    }
}

/// Near plane distance of a perspective shadow view of reach `range`:
/// `max(range × 0.002, 0.01)`, but never more than half the range. A non-finite or
/// non-positive range gives 0.01.
pub fn perspective_near(range: f32) -> f32 {
    if !(range.is_finite() && range > 0.0) {
        return 0.01;
    }
    (range * 0.002).max(0.01).min(range * 0.5)
}

/// A square reversed-Z perspective projection: `tan(half fov) = tan_half`, depth 1 at view
/// depth `near` and 0 at `far` (an infinite `far` gives the infinite reversed projection).
fn reversed_perspective(tan_half: f32, near: f32, far: f32) -> Mat4 {
    let s = tan_half.recip();
    // clip.z = a z + b, clip.w = -z: (b - a n) / n = 1 and (b - a f) / f = 0.
    let (a, b) = if far.is_finite() && far > near {
        (near / (far - near), near * far / (far - near))
    } else {
        (0.0, near)
    };
    Mat4::from_cols(
        Vec4::new(s, 0.0, 0.0, 0.0),
        Vec4::new(0.0, s, 0.0, 0.0),
        Vec4::new(0.0, 0.0, a, -1.0),
        Vec4::new(0.0, 0.0, b, 0.0),
    )
}

/// A reversed-Z orthographic projection: `ndc.xy = xy / half + offset`, depth 1 at view depth
/// `near` and 0 at `far` (view depth is `-z`; `near` may be negative).
fn reversed_orthographic(half: f32, offset_x: f32, offset_y: f32, near: f32, far: f32) -> Mat4 {
    let s = half.recip();
    // depth = a z + b: b - a n = 1 and b - a f = 0.
    let a = (far - near).recip();
    Mat4::from_cols(
        Vec4::new(s, 0.0, 0.0, 0.0),
        Vec4::new(0.0, s, 0.0, 0.0),
        Vec4::new(0.0, 0.0, a, 0.0),
        Vec4::new(offset_x, offset_y, far * a, 1.0),
    )
}

/// An up vector that is never parallel to the unit direction `dir`.
fn up_for(dir: Vec3) -> Vec3 {
    if dir.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y }
}

/// View matrix of an eye at `eye` looking along `dir` (normalised here; zero → −Z).
fn look_along(eye: Vec3, dir: Vec3) -> Mat4 {
    let dir = dir.normalize_or(Vec3::NEG_Z);
    look_to_mat4(eye, dir, up_for(dir))
}

/// The view of a spot light at `position` pointing along `direction`, covering the cone of half
/// angle `outer_cone` (radians, clamped to `[1e-3, MAX_SPOT_HALF_ANGLE]`) inscribed in the square
/// region, from [`perspective_near`]`(range)` to `range`, into a `side`-texel region.
pub fn spot_view(
    position: Vec3,
    direction: Vec3,
    outer_cone: f32,
    range: f32,
    side: u32,
) -> LightView {
    let tan_half = outer_cone.clamp(1e-3, MAX_SPOT_HALF_ANGLE).tan();
    let projection = reversed_perspective(tan_half, perspective_near(range), range);
    LightView {
        clip_from_world: projection * look_along(position, direction),
        texel_world: 2.0 * tan_half / side.max(1) as f32,
        orthographic: false,
        split_far: 0.0,
    }
}
