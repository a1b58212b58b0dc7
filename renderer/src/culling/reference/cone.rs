//! The reference's own bounding sphere of a spot light, found from the geometry of what the
//! light reaches, not from the closed form the renderer uses ([`super::LightSphere::spot`]).
//!
//! A spot light of range `r` and outer half-angle `θ` reaches the spherical sector
//! `{apex + s · (cos φ · axis + sin φ · u) : 0 ≤ s ≤ r, 0 ≤ φ ≤ θ, u ⟂ axis, |u| = 1}`.
//! By symmetry its smallest enclosing sphere is centred on the axis, at `apex + t · axis`.
//! For such a centre the farthest point of the sector is found by direct reasoning: along a
//! ray of the sector the squared distance `s² − 2 s t cos φ + t²` is convex in `s`, so it peaks
//! at the apex (`s = 0`) or on the far cap (`s = r`); on the cap it grows as `t cos φ` falls,
//! so it peaks on the rim (`φ = θ`) when `t ≥ 0` and at the axis tip (`φ = 0`) when `t < 0`.
//! The enclosing radius `R(t)` is the largest of these distances, a maximum of convex
//! functions of `t` and so convex: a golden-section search over `t ∈ [−r, r]` finds its
//! minimum. [`sector_points`] samples the sector for containment tests.

use glam::Vec3;

use super::LightSphere;

/// The farthest distance from `apex + t · axis` to the sector of range `range` and half-angle
/// `half_angle` (radians, 0 to π).
fn enclosing_radius(t: f64, half_angle: f64, range: f64) -> f64 {
    let cap = |phi: f64| {
        (range * range - 2.0 * range * t * phi.cos() + t * t)
            .max(0.0)
            .sqrt()
    };
    let far = if t >= 0.0 { cap(half_angle) } else { cap(0.0) };
    t.abs().max(far)
}

/// The smallest sphere holding a spot light's sector: apex `apex`, unit `axis`, half-angle
/// `half_angle` radians (0 to π), range `range`. Found by golden-section search (in `f64`) of
/// the centre along the axis; the radius is that of the best centre found, widened by a part
/// in 10⁵ so that rounding cannot leave a sector point outside.
pub fn spot_bounding_sphere(apex: Vec3, axis: Vec3, half_angle: f32, range: f32) -> LightSphere {
    let (angle, r) = (f64::from(half_angle), f64::from(range));
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let (mut lo, mut hi) = (-r, r);
    for _ in 0..100 {
        let a = hi - ratio * (hi - lo);
        let b = lo + ratio * (hi - lo);
        if enclosing_radius(a, angle, r) <= enclosing_radius(b, angle, r) {
            hi = b;
        } else {
            lo = a;
        }
    }
    let t = 0.5 * (lo + hi);
    LightSphere {
        center: apex + axis * t as f32,
        radius: (enclosing_radius(t, angle, r) * (1.0 + 1.0e-5)) as f32,
    }
}

/// Points of a spot light's sector: the apex, the axis tip, `rim` points round the rim, and
/// for each of `rings` half-angles from 0 to `half_angle` and `rings` distances from 0 to
/// `range`, `rim` points round the axis.
pub fn sector_points(
    apex: Vec3,
    axis: Vec3,
    half_angle: f32,
    range: f32,
    rings: u32,
    rim: u32,
) -> Vec<Vec3> {
    let (u, v) = axis.any_orthonormal_pair();
    let ray = |phi: f32, around: f32| {
        axis * phi.cos() + (u * around.cos() + v * around.sin()) * phi.sin()
    };
    let mut points = vec![apex, apex + axis * range];
    for k in 0..rim {
        let around = std::f32::consts::TAU * k as f32 / rim as f32;
        points.push(apex + ray(half_angle, around) * range);
        for i in 1..=rings {
            let phi = half_angle * i as f32 / rings as f32;
            for j in 1..=rings {
                points.push(apex + ray(phi, around) * (range * j as f32 / rings as f32));
            }
        }
    }
    points
}

#[cfg(test)]
#[path = "cone_tests.rs"]
mod tests;
