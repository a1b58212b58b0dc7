//! Spot views, cube faces and the caster frusta against their conventions: reversed depth,
//! cones and guard bands inside their regions, the face rule over the whole sphere.

use super::*;
use std::f32::consts::{FRAC_PI_4, PI};

pub(super) fn aabb(min: Vec3, max: Vec3) -> Aabb {
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
