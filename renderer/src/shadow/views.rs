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

use glam::camera::rh::view::look_to_mat4;
use glam::{Mat4, Vec3, Vec4};

use crate::culling::reference::Plane;
use crate::scene::Aabb;

/// Number of directional cascades.
pub const CASCADE_COUNT: usize = 4;

/// Weight of the logarithmic split against the uniform one in [`cascade_splits`].
pub const CASCADE_SPLIT_LAMBDA: f32 = 0.75;

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

/// Forward axis of each cube face, in the order +X, −X, +Y, −Y, +Z, −Z.
pub const CUBE_FACE_DIRECTIONS: [Vec3; 6] = [
    Vec3::X,
    Vec3::NEG_X,
    Vec3::Y,
    Vec3::NEG_Y,
    Vec3::Z,
    Vec3::NEG_Z,
];

/// Up axis of each cube face's view (the region's `+y`); the shader samples a face through its
/// matrix, so this orientation need not match a hardware cube map's.
pub const CUBE_FACE_UPS: [Vec3; 6] = [Vec3::Y, Vec3::Y, Vec3::Z, Vec3::NEG_Z, Vec3::Y, Vec3::Y];

/// The cube face that holds direction `dir` (from the light to the point), the rule the GPU
/// mirrors exactly:
///
/// ```text
/// a = abs(dir)
/// if a.x >= a.y && a.x >= a.z { face = select(1, 0, dir.x >= 0.0) }   // +X 0, −X 1
/// else if a.y >= a.z          { face = select(3, 2, dir.y >= 0.0) }   // +Y 2, −Y 3
/// else                        { face = select(5, 4, dir.z >= 0.0) }   // +Z 4, −Z 5
/// ```
///
/// Ties go to x, then y; a zero component counts as positive (so the zero vector is face 0).
pub fn cube_face(dir: Vec3) -> usize {
    let a = dir.abs();
    if a.x >= a.y && a.x >= a.z {
        if dir.x >= 0.0 { 0 } else { 1 }
    } else if a.y >= a.z {
        if dir.y >= 0.0 { 2 } else { 3 }
    } else if dir.z >= 0.0 {
        4
    } else {
        5
    }
}

/// `tan(half fov)` of a cube face with `guard` guard texels on each side of a `side`-texel
/// region: `side / (side − 2 guard)`. `guard` is clamped so at least one inner texel remains.
pub fn cube_tan_half_fov(side: u32, guard: u32) -> f32 {
    let side = side.max(1);
    let guard = guard.min((side - 1) / 2);
    side as f32 / (side - 2 * guard) as f32
}

/// Guard band: each face's field of view is widened so the outermost `guard` texels of a
/// `side`-texel region lie beyond the face's 90° edge: tan(half fov) = side / (side - 2 guard)
/// (see [`cube_tan_half_fov`]). Faces in the order +X, −X, +Y, −Y, +Z, −Z
/// ([`CUBE_FACE_DIRECTIONS`], [`CUBE_FACE_UPS`]); a shader picks the face with [`cube_face`]
/// of `p − position`. Depth runs from [`perspective_near`]`(range)` to `range` along each
/// face's axis (not radially).
pub fn cube_views(position: Vec3, range: f32, side: u32, guard: u32) -> [LightView; 6] {
    let tan_half = cube_tan_half_fov(side, guard);
    let projection = reversed_perspective(tan_half, perspective_near(range), range);
    let texel_world = 2.0 * tan_half / side.max(1) as f32;
    std::array::from_fn(|face| LightView {
        clip_from_world: projection
            * look_to_mat4(position, CUBE_FACE_DIRECTIONS[face], CUBE_FACE_UPS[face]),
        texel_world,
        orthographic: false,
        split_far: 0.0,
    })
}

/// The far view depth of each cascade over `[near, distance]`: the practical split, `λ` =
/// [`CASCADE_SPLIT_LAMBDA`] of the logarithmic split plus `1 − λ` of the uniform one. The last
/// is exactly `distance`. `near` is clamped to at least 1e-4 and `distance` to more than `near`.
pub fn cascade_splits(near: f32, distance: f32) -> [f32; CASCADE_COUNT] {
    let near = near.max(1e-4);
    let distance = distance.max(near * 1.001);
    std::array::from_fn(|i| {
        if i + 1 == CASCADE_COUNT {
            return distance;
        }
        let t = (i + 1) as f32 / CASCADE_COUNT as f32;
        let log = near * (distance / near).powf(t);
        let uniform = near + (distance - near) * t;
        CASCADE_SPLIT_LAMBDA * log + (1.0 - CASCADE_SPLIT_LAMBDA) * uniform
    })
}

/// The bounding sphere of the camera frustum slice between view depths `near` and `far`, whose
/// corners lie at `(±tan_x d, ±tan_y d, −d)`: its centre's view depth and its radius. It is
/// centred on the view axis, so it depends on the slice only, not on the camera's orientation.
pub fn slice_bounding_sphere(tan_x: f32, tan_y: f32, near: f32, far: f32) -> (f32, f32) {
    let k2 = tan_x * tan_x + tan_y * tan_y;
    // Equidistant from the near and far corners, unless that lies beyond the far plane.
    let center = ((far + near) * (1.0 + k2) * 0.5).min(far);
    let to_near = ((center - near).powi(2) + near * near * k2).sqrt();
    let to_far = ((far - center).powi(2) + far * far * k2).sqrt();
    (center, to_near.max(to_far))
}

/// Four cascades of a directional light over the camera's view depth [near, distance], split
/// practically (lambda = 0.75 between log and uniform, [`cascade_splits`]), each fitted with a
/// bounding sphere of the split's frustum slice ([`slice_bounding_sphere`]: its size does not
/// change as the camera turns), an orthographic projection whose origin is snapped to whole
/// texels in light space (stable: moving the camera by less than a texel does not shift the
/// texel grid relative to the world), and a depth range extended towards the light to include
/// every caster of `scene_bounds`.
///
/// `camera_world_from_view` must be rigid (the inverse of the camera's view matrix); `fovy` is
/// the vertical field of view, `aspect` width / height. The region is one texel wider than the
/// sphere on each side, so snapping never pushes the slice out of it. Light space is a fixed
/// rotation of the world (it depends on `light_direction` only), with its origin at the world's.
#[expect(
    clippy::too_many_arguments,
    reason = "the camera and the light, spelled out"
)]
pub fn cascade_views(
    camera_world_from_view: Mat4,
    fovy: f32,
    aspect: f32,
    near: f32,
    distance: f32,
    light_direction: Vec3,
    side: u32,
    scene_bounds: &Aabb,
) -> [LightView; 4] {
    let tan_y = (fovy.clamp(1e-3, std::f32::consts::PI - 1e-3) * 0.5).tan();
    let tan_x = tan_y * aspect.max(1e-3);
    let light_from_world = look_along(Vec3::ZERO, light_direction);
    let near = near.max(1e-4);
    let splits = cascade_splits(near, distance);
    // The nearest caster's light-space z (the light looks down −z, so the largest z).
    let scene_light = scene_bounds.transformed(light_from_world);
    let caster_z =
        (!scene_light.is_empty() && scene_light.max.z.is_finite()).then_some(scene_light.max.z);
    std::array::from_fn(|i| {
        let slice_near = if i == 0 { near } else { splits[i - 1] };
        let (center_depth, radius) = slice_bounding_sphere(tan_x, tan_y, slice_near, splits[i]);
        let center_world =
            camera_world_from_view.transform_point3(Vec3::new(0.0, 0.0, -center_depth));
        let sphere = Sphere {
            center: light_from_world.transform_point3(center_world),
            radius,
        };
        let mut view = cascade_view(sphere, side, caster_z);
        view.clip_from_world *= light_from_world;
        view.split_far = splits[i];
        view
    })
}

/// A sphere in light space.
#[derive(Debug, Clone, Copy)]
struct Sphere {
    center: Vec3,
    radius: f32,
}

/// The light-space (not yet world) view of one cascade: the sphere's square, one texel wider
/// on each side, its centre snapped to whole texels, depth from the nearer of the sphere and
/// the casters (`caster_z`) to the sphere's far side, padded by a texel.
fn cascade_view(sphere: Sphere, side: u32, caster_z: Option<f32>) -> LightView {
    let side = side.max(1) as f32;
    let half = sphere.radius / (1.0 - 2.0 / side).max(0.5);
    let texel = 2.0 * half / side;
    // Whole-texel centre: ndc = (x − k texel) / half = x / half − k (2 / side).
    let kx = (sphere.center.x / texel).round();
    let ky = (sphere.center.y / texel).round();
    let depth = -sphere.center.z;
    let mut near = depth - sphere.radius - texel;
    if let Some(z) = caster_z {
        near = near.min(-z - texel);
    }
    let far = depth + sphere.radius + texel;
    LightView {
        clip_from_world: reversed_orthographic(half, -kx * 2.0 / side, -ky * 2.0 / side, near, far),
        texel_world: texel,
        orthographic: true,
        split_far: 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::{FRAC_PI_4, PI};

    fn aabb(min: Vec3, max: Vec3) -> Aabb {
        Aabb { min, max }
    }

    /// Unit directions spread over the sphere (Fibonacci), plus every face centre, edge midpoint
    /// and corner of the cube, and points just either side of the edges.
    fn sample_directions() -> Vec<Vec3> {
        let n = 2000;
        let golden = PI * (3.0 - 5f32.sqrt());
        let mut dirs: Vec<Vec3> = (0..n)
            .map(|i| {
                let y = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
                let r = (1.0 - y * y).sqrt();
                let phi = golden * i as f32;
                Vec3::new(r * phi.cos(), y, r * phi.sin())
            })
            .collect();
        for x in [-1.0f32, 0.0, 1.0] {
            for y in [-1.0f32, 0.0, 1.0] {
                for z in [-1.0f32, 0.0, 1.0] {
                    let d = Vec3::new(x, y, z);
                    if d != Vec3::ZERO {
                        dirs.push(d.normalize());
                        for e in [1e-6f32, -1e-6, 1e-3, -1e-3] {
                            dirs.push((d + Vec3::splat(e) * Vec3::new(1.0, -2.0, 3.0)).normalize());
                        }
                    }
                }
            }
        }
        dirs
    }

    // ---- spot ----

    #[test]
    fn spot_axis_projects_to_centre_with_reversed_depth() {
        let pos = Vec3::new(1.0, 4.0, -2.0);
        let dir = Vec3::new(0.3, -1.0, 0.2).normalize();
        let v = spot_view(pos, dir, 0.5, 20.0, 1024);
        assert!(!v.orthographic);
        assert_eq!(v.split_far, 0.0);
        let near = v.ndc(pos + dir * 1.0);
        let far = v.ndc(pos + dir * 15.0);
        for p in [near, far] {
            assert!(p.x.abs() < 1e-5 && p.y.abs() < 1e-5, "{p}");
            assert!(p.z > 0.0 && p.z < 1.0, "{p}");
        }
        assert!(near.z > far.z, "reversed Z: {near} vs {far}");
        // The ends of the range.
        let n = perspective_near(20.0);
        assert!((v.ndc(pos + dir * n).z - 1.0).abs() < 1e-4);
        assert!(v.ndc(pos + dir * 20.0).z.abs() < 1e-4);
        assert!((v.texel_world - 2.0 * 0.5f32.tan() / 1024.0).abs() < 1e-9);
    }

    #[test]
    fn spot_cone_inside_and_outside() {
        let pos = Vec3::new(-3.0, 2.0, 5.0);
        let dir = Vec3::new(0.0, -1.0, 0.0); // straight down: exercises the up-vector fallback
        let outer = 0.6f32;
        let v = spot_view(pos, dir, outer, 10.0, 512);
        let (right, up) = (Vec3::X, Vec3::Z);
        for k in 0..32 {
            let az = k as f32 / 32.0 * 2.0 * PI;
            let ring = right * az.cos() + up * az.sin();
            // Inside the cone: inside the region.
            let inside = v.ndc(pos + (dir + ring * (outer * 0.99).tan()).normalize() * 5.0);
            assert!(inside.x.abs() <= 1.0 && inside.y.abs() <= 1.0, "{inside}");
            assert!(inside.z > 0.0 && inside.z < 1.0);
            // Beyond the square's circumscribed cone: outside the region, whatever the azimuth.
            let beyond = (dir + ring * outer.tan() * 2f32.sqrt() * 1.05).normalize();
            let out = v.ndc(pos + beyond * 5.0);
            assert!(out.x.abs() > 1.0 || out.y.abs() > 1.0, "{out}");
            assert!(!v.frustum().contains_point(pos + beyond * 5.0));
        }
        // Just beyond the cone along a region axis.
        let side = v.ndc(pos + (dir + Vec3::X * (outer * 1.1).tan()) * 3.0);
        assert!(side.x.abs() > 1.0, "{side}");
    }

    #[test]
    fn perspective_near_is_small_and_safe() {
        assert_eq!(perspective_near(100.0), 0.2);
        assert_eq!(perspective_near(1.0), 0.01);
        assert_eq!(perspective_near(0.004), 0.002);
        assert_eq!(perspective_near(f32::INFINITY), 0.01);
        assert_eq!(perspective_near(-1.0), 0.01);
        // A non-finite range still gives a usable (infinite reversed) projection.
        let v = spot_view(Vec3::ZERO, Vec3::NEG_Z, 0.4, f32::INFINITY, 256);
        let d = v.ndc(Vec3::new(0.0, 0.0, -1e6)).z;
        assert!(d.is_finite() && d > 0.0 && d < 1.0);
    }

    // ---- cube ----

    #[test]
    fn cube_face_rule() {
        let cases = [
            (Vec3::new(1.0, 1.0, 1.0), 0),
            (Vec3::new(1.0, 1.0, 0.0), 0),
            (Vec3::new(1.0, -1.0, 0.0), 0),
            (Vec3::new(-1.0, 1.0, 0.0), 1),
            (Vec3::new(-1.0, -1.0, -1.0), 1),
            (Vec3::new(0.0, 1.0, 1.0), 2),
            (Vec3::new(0.0, -1.0, 1.0), 3),
            (Vec3::new(0.0, -1.0, -1.0), 3),
            (Vec3::new(0.0, 0.0, 1.0), 4),
            (Vec3::new(0.0, 0.0, -1.0), 5),
            (Vec3::new(0.2, 0.1, -0.9), 5),
            (Vec3::new(0.2, 0.9, -0.1), 2),
            (Vec3::ZERO, 0),
            (Vec3::new(-0.0, 0.0, 0.0), 0),
        ];
        for (d, face) in cases {
            assert_eq!(cube_face(d), face, "{d}");
        }
        for d in sample_directions() {
            let f = cube_face(d);
            let axis = CUBE_FACE_DIRECTIONS[f];
            assert!(d.dot(axis) >= d.abs().max_element() - 1e-7, "{d} -> {f}");
        }
    }

    #[test]
    fn cube_every_direction_lands_in_its_face() {
        let pos = Vec3::new(2.0, -1.0, 3.0);
        let range = 12.0;
        for (side, guard) in [(256u32, 0u32), (256, 2), (64, 4), (1024, 1), (7, 3)] {
            let views = cube_views(pos, range, side, guard);
            let inner = cube_tan_half_fov(side, guard).recip();
            if side == 256 {
                assert!((inner - (side - 2 * guard) as f32 / side as f32).abs() < 1e-6);
            }
            for d in sample_directions() {
                let v = &views[cube_face(d)];
                for dist in [0.5, 6.0, 11.9] {
                    let p = v.ndc(pos + d * dist);
                    let m = p.x.abs().max(p.y.abs());
                    // Without a guard band, edge and corner directions sit exactly on the
                    // region's border: allow rounding there; with one, the margin is real.
                    let slack = if guard == 0 { 1e-6 } else { 0.0 };
                    assert!(1.0 - m >= -slack, "margin {} for {d}", 1.0 - m);
                    assert!(
                        m <= inner + 1e-5,
                        "{d}: {m} > inner {inner} ({side}, {guard})"
                    );
                    assert!(p.z > 0.0 && p.z < 1.0, "{d}: depth {}", p.z);
                    // With a guard band every face direction is strictly inside the frustum
                    // (without one, edge directions lie on a side plane, up to rounding).
                    if guard > 0 {
                        assert!(v.frustum().contains_point(pos + d * dist), "{d}");
                    }
                }
            }
        }
    }

    #[test]
    fn cube_face_axes_project_to_centre_and_guard_band_is_beyond_edge() {
        let pos = Vec3::new(-4.0, 0.5, 1.0);
        let (side, guard) = (128u32, 4u32);
        let views = cube_views(pos, 30.0, side, guard);
        for (face, v) in views.iter().enumerate() {
            let axis = CUBE_FACE_DIRECTIONS[face];
            let (a, b) = (v.ndc(pos + axis), v.ndc(pos + axis * 20.0));
            for p in [a, b] {
                assert!(p.x.abs() < 1e-6 && p.y.abs() < 1e-6, "face {face}: {p}");
            }
            assert!(a.z > b.z && a.z < 1.0 && b.z > 0.0);
            // Up maps to +y.
            assert!(v.ndc(pos + axis + CUBE_FACE_UPS[face] * 0.5).y > 0.0);
            assert!((v.texel_world - 2.0 / (side - 2 * guard) as f32).abs() < 1e-7);
            // A direction past the 90° edge by half the guard band is still in the region,
            // in the guard texels.
            let up = CUBE_FACE_UPS[face];
            let over = 1.0 + guard as f32 / (side - 2 * guard) as f32;
            let p = v.ndc(pos + axis + up * over);
            let edge = (side - 2 * guard) as f32 / side as f32;
            assert!(p.y > edge && p.y < 1.0, "face {face}: {}", p.y);
        }
    }

    // ---- cascades ----

    fn camera(eye: Vec3, target: Vec3) -> Mat4 {
        glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y).inverse()
    }

    const FOVY: f32 = 1.0;
    const ASPECT: f32 = 16.0 / 9.0;
    const NEAR: f32 = 0.1;
    const DIST: f32 = 60.0;
    const SIDE: u32 = 2048;

    fn scene() -> Aabb {
        aabb(Vec3::new(-80.0, -2.0, -80.0), Vec3::new(80.0, 40.0, 80.0))
    }

    fn light() -> Vec3 {
        Vec3::new(0.4, -1.0, 0.25).normalize()
    }

    fn cascades(world_from_view: Mat4) -> [LightView; 4] {
        cascade_views(
            world_from_view,
            FOVY,
            ASPECT,
            NEAR,
            DIST,
            light(),
            SIDE,
            &scene(),
        )
    }

    /// Points of the camera frustum slice between view depths `n` and `f`: its corners and a grid
    /// through its volume.
    fn slice_points(world_from_view: Mat4, n: f32, f: f32) -> Vec<Vec3> {
        let tan_y = (FOVY * 0.5).tan();
        let tan_x = tan_y * ASPECT;
        let mut out = Vec::new();
        for i in 0..=6 {
            let d = n + (f - n) * i as f32 / 6.0;
            for u in [-1.0, -0.5, 0.0, 0.7, 1.0] {
                for v in [-1.0, -0.3, 0.0, 0.5, 1.0] {
                    let p = Vec3::new(u * tan_x * d, v * tan_y * d, -d);
                    out.push(world_from_view.transform_point3(p));
                }
            }
        }
        out
    }

    #[test]
    fn splits_increase_and_end_at_distance() {
        let s = cascade_splits(NEAR, DIST);
        assert!(s[0] > NEAR);
        assert!(s.windows(2).all(|w| w[0] < w[1]), "{s:?}");
        assert_eq!(s[3], DIST);
        // Between the logarithmic and the uniform split.
        let log1 = NEAR * (DIST / NEAR).powf(0.25);
        let uni1 = NEAR + (DIST - NEAR) * 0.25;
        assert!((s[0] - (0.75 * log1 + 0.25 * uni1)).abs() < 1e-4);
        let views = cascades(camera(Vec3::new(3.0, 2.0, 10.0), Vec3::ZERO));
        for (v, split) in views.iter().zip(s) {
            assert_eq!(v.split_far, split);
            assert!(v.orthographic);
        }
        // Degenerate input still gives increasing splits.
        let d = cascade_splits(0.0, 0.0);
        assert!(d.windows(2).all(|w| w[0] < w[1]), "{d:?}");
    }

    #[test]
    fn every_slice_point_projects_inside_its_cascade() {
        let cams = [
            camera(Vec3::new(3.0, 2.0, 10.0), Vec3::ZERO),
            camera(Vec3::new(-20.0, 8.0, 5.0), Vec3::new(10.0, 0.0, -3.0)),
            camera(Vec3::new(0.0, 30.0, 0.1), Vec3::ZERO),
        ];
        for cam in cams {
            let views = cascades(cam);
            let mut n = NEAR;
            for v in &views {
                for p in slice_points(cam, n, v.split_far) {
                    let q = v.ndc(p);
                    assert!(q.x.abs() <= 1.0 && q.y.abs() <= 1.0, "{q}");
                    assert!(q.z >= 0.0 && q.z <= 1.0, "{q}");
                    assert!(v.frustum().contains_point(p));
                }
                n = v.split_far;
            }
        }
    }

    #[test]
    fn cascade_size_does_not_change_as_camera_turns() {
        let eye = Vec3::new(5.0, 3.0, 5.0);
        let a = cascades(camera(eye, Vec3::ZERO));
        let b = cascades(camera(eye, Vec3::new(-30.0, 10.0, 7.0)));
        for (a, b) in a.iter().zip(&b) {
            assert_eq!(a.texel_world, b.texel_world);
        }
        // Larger cascades for farther splits.
        assert!(a.windows(2).all(|w| w[0].texel_world < w[1].texel_world));
    }

    fn texel_fraction(v: &LightView, p: Vec3) -> (f32, f32) {
        let q = v.ndc(p);
        let u = (q.x * 0.5 + 0.5) * SIDE as f32;
        let w = (q.y * 0.5 + 0.5) * SIDE as f32;
        (u - u.floor(), w - w.floor())
    }

    /// Distance between two fractions on the unit circle (0.999 and 0.001 are close).
    fn circular(a: f32, b: f32) -> f32 {
        let d = (a - b).abs();
        d.min(1.0 - d)
    }

    #[test]
    fn snapping_keeps_the_texel_grid_fixed_in_the_world() {
        let target = Vec3::new(1.0, 0.0, -2.0);
        let eye = Vec3::new(4.0, 3.0, 9.0);
        let base = cascades(camera(eye, target));
        let world_points = [
            Vec3::new(0.3, 0.2, -1.7),
            Vec3::new(2.11, 0.0, 0.37),
            Vec3::new(-1.234, 1.5, -3.21),
        ];
        let mut moved_any = false;
        for offset in [
            Vec3::new(0.013, -0.007, 0.021),
            Vec3::new(0.0004, 0.0, 0.0),
            Vec3::new(0.37, 0.11, -0.52),
        ] {
            let moved = cascades(camera(eye + offset, target + offset));
            for (a, b) in base.iter().zip(&moved) {
                assert_eq!(a.texel_world, b.texel_world);
                moved_any |= a.clip_from_world != b.clip_from_world;
                for p in world_points {
                    let (fa, fb) = (texel_fraction(a, p), texel_fraction(b, p));
                    assert!(circular(fa.0, fb.0) < 0.01, "x: {fa:?} vs {fb:?}");
                    assert!(circular(fa.1, fb.1) < 0.01, "y: {fa:?} vs {fb:?}");
                }
            }
        }
        assert!(
            moved_any,
            "the larger offset must move at least one cascade"
        );
    }

    #[test]
    fn casters_towards_the_light_are_inside_the_depth_range() {
        let cam = camera(Vec3::new(3.0, 2.0, 10.0), Vec3::new(0.0, 0.0, -5.0));
        let views = cascades(cam);
        let bounds = scene();
        let inside = |p: Vec3| p.cmpge(bounds.min).all() && p.cmple(bounds.max).all();
        let mut n = NEAR;
        for v in &views {
            for receiver in slice_points(cam, n, v.split_far) {
                let r = v.ndc(receiver);
                let mut t = 0.5;
                loop {
                    let caster = receiver - light() * t;
                    if !inside(caster) {
                        break;
                    }
                    let c = v.ndc(caster);
                    assert!(c.z >= 0.0 && c.z <= 1.0, "caster depth {}", c.z);
                    assert!(c.z > r.z, "caster nearer the light than its receiver");
                    assert!((c.x - r.x).abs() < 1e-3 && (c.y - r.y).abs() < 1e-3);
                    t *= 1.7;
                }
            }
            // The corner of the scene nearest the light.
            let corner = Vec3::select(light().cmplt(Vec3::ZERO), bounds.max, bounds.min);
            let d = v.ndc(corner).z;
            assert!((0.0..=1.0).contains(&d), "{d}");
            n = v.split_far;
        }
        // An empty scene only bounds the slice.
        let empty = cascade_views(cam, FOVY, ASPECT, NEAR, DIST, light(), SIDE, &Aabb::EMPTY);
        assert!(empty.iter().all(|v| v.clip_from_world.is_finite()));
    }

    #[test]
    fn slice_sphere_contains_corners() {
        for (tx, ty, n, f) in [
            (0.5, 0.3, 0.1, 2.0),
            (2.0, 1.5, 1.0, 1.5),
            (0.1, 0.1, 10.0, 60.0),
        ] {
            let (c, r) = slice_bounding_sphere(tx, ty, n, f);
            for d in [n, f] {
                let corner = Vec3::new(tx * d, ty * d, -d);
                assert!(corner.distance(Vec3::new(0.0, 0.0, -c)) <= r * (1.0 + 1e-6));
            }
        }
    }

    // ---- frustum ----

    #[test]
    fn frustum_boxes_and_reversed_z_planes() {
        // A spot looking down −Z from the origin, 90° wide, range 10.
        let v = spot_view(Vec3::ZERO, Vec3::NEG_Z, FRAC_PI_4, 10.0, 256);
        let f = v.frustum();
        let near = perspective_near(10.0);
        // Near plane (depth 1) and far plane (depth 0), in that order in `planes`.
        let planes = f.planes();
        assert!((planes[4].normal - Vec3::NEG_Z).length() < 1e-5);
        assert!((planes[4].d + near).abs() < 1e-4, "{:?}", planes[4]);
        assert!((planes[5].normal - Vec3::Z).length() < 1e-5);
        assert!((planes[5].d - 10.0).abs() < 1e-3, "{:?}", planes[5]);
        assert!(!f.contains_point(Vec3::new(0.0, 0.0, -near * 0.5)));
        assert!(f.contains_point(Vec3::new(0.0, 0.0, -near * 2.0)));
        assert!(f.contains_point(Vec3::new(0.0, 0.0, -9.9)));
        assert!(!f.contains_point(Vec3::new(0.0, 0.0, -10.1)));
        assert!(!f.contains_point(Vec3::new(0.0, 0.0, 1.0)));
        assert!(!f.contains_point(Vec3::new(6.0, 0.0, -5.0)));
        assert!(f.contains_point(Vec3::new(4.0, -4.0, -5.0)));

        let b = |min: [f32; 3], max: [f32; 3]| aabb(Vec3::from(min), Vec3::from(max));
        // Inside.
        assert!(f.intersects_aabb(&b([-1.0, -1.0, -6.0], [1.0, 1.0, -4.0])));
        // Outside: behind the light, beyond the far plane, past the left and top sides.
        assert!(!f.intersects_aabb(&b([-1.0, -1.0, 0.5], [1.0, 1.0, 2.0])));
        assert!(!f.intersects_aabb(&b([-1.0, -1.0, -12.0], [1.0, 1.0, -10.5])));
        assert!(!f.intersects_aabb(&b([-9.0, -1.0, -3.0], [-4.0, 1.0, -2.0])));
        assert!(!f.intersects_aabb(&b([-1.0, 4.0, -3.0], [1.0, 5.0, -2.0])));
        // Between the eye and the near plane.
        assert!(!f.intersects_aabb(&b([-1e-3, -1e-3, -near * 0.9], [1e-3, 1e-3, -near * 0.1])));
        // Straddling one plane: the left side, the far plane, the near plane.
        assert!(f.intersects_aabb(&b([-5.0, -1.0, -4.0], [-3.0, 1.0, -3.0])));
        assert!(f.intersects_aabb(&b([-1.0, -1.0, -11.0], [1.0, 1.0, -9.0])));
        assert!(f.intersects_aabb(&b([-1e-3, -1e-3, -near * 2.0], [1e-3, 1e-3, 1.0])));
        // Enclosing the whole frustum.
        assert!(f.intersects_aabb(&b([-100.0; 3], [100.0; 3])));
        // Empty.
        assert!(!f.intersects_aabb(&Aabb::EMPTY));
    }

    #[test]
    fn frustum_of_an_orthographic_cascade() {
        let cam = camera(Vec3::new(0.0, 2.0, 10.0), Vec3::ZERO);
        let views = cascades(cam);
        let f = views[0].frustum();
        let inv = views[0].clip_from_world.inverse();
        // Points just inside and outside each clip bound.
        for (clip, inside) in [
            (Vec3::new(0.0, 0.0, 0.5), true),
            (Vec3::new(0.99, -0.99, 0.01), true),
            (Vec3::new(0.0, 0.0, 0.99), true),
            (Vec3::new(1.01, 0.0, 0.5), false),
            (Vec3::new(0.0, -1.01, 0.5), false),
            (Vec3::new(0.0, 0.0, 1.01), false),
            (Vec3::new(0.0, 0.0, -0.01), false),
        ] {
            let p = inv.project_point3(clip);
            assert_eq!(f.contains_point(p), inside, "{clip}");
        }
        let centre = inv.project_point3(Vec3::new(0.0, 0.0, 0.5));
        let tiny = |c: Vec3| aabb(c - 0.01, c + 0.01);
        assert!(f.intersects_aabb(&tiny(centre)));
        let outside = inv.project_point3(Vec3::new(0.0, 0.0, 1.5));
        assert!(!f.intersects_aabb(&tiny(outside)));
    }
}
