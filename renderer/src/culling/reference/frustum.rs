//! Tile frustum planes from the projection matrix (Gribb/Hartmann), and the sphere test.

use glam::{Mat4, Vec3};

use super::Plane;

/// The four side planes of the screen rectangle `[x0, x1] × [y0, y1]` in NDC, in view space.
///
/// A view-space point `v` is inside when `x0 ≤ clip.x / clip.w ≤ x1` (and likewise for y) with
/// `clip = P v`, which is linear in `v` once multiplied by `clip.w > 0`: each side is a row
/// combination of `P`.
pub fn tile_side_planes(projection: Mat4, x0: f32, x1: f32, y0: f32, y1: f32) -> [Plane; 4] {
    let (r0, r1, r3) = (projection.row(0), projection.row(1), projection.row(3));
    [
        Plane::from_vec4(r0 - x0 * r3),
        Plane::from_vec4(x1 * r3 - r0),
        Plane::from_vec4(r1 - y0 * r3),
        Plane::from_vec4(y1 * r3 - r1),
    ]
}

/// The smallest signed margin by which a sphere clears the planes: `min(n · c + d + r)`.
/// The sphere may intersect the convex region only if the margin is ≥ 0.
pub fn sphere_margin(planes: &[Plane], center: Vec3, radius: f32) -> f32 {
    planes
        .iter()
        .map(|p| p.distance(center) + radius)
        .fold(f32::INFINITY, f32::min)
}
