//! The six guard-banded perspective faces of a point light, and the rule that picks a
//! direction's face.

use glam::Vec3;
use glam::camera::rh::view::look_to_mat4;

use super::{LightView, perspective_near, reversed_perspective};

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
#[cfg(any(test, feature = "internals"))]
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
