//! Directional cascades: splits, every point of a slice inside its cascade, sizes that do
//! not change as the camera turns, a texel grid fixed in the world, casters inside the depth
//! range, and the frustum of an orthographic cascade.

use super::tests::aabb;
use super::*;

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
        CameraLens::perspective(FOVY, ASPECT),
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
    let empty = cascade_views(
        cam,
        CameraLens::perspective(FOVY, ASPECT),
        NEAR,
        DIST,
        light(),
        SIDE,
        &Aabb::EMPTY,
    );
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

#[test]
fn an_orthographic_camera_gets_cascades_around_its_box() {
    let (hw, hh) = (20.0, 12.0);
    let projection = glam::camera::rh::proj::directx::orthographic(-hw, hw, -hh, hh, NEAR, 200.0);
    let lens = CameraLens::of(projection);
    assert_eq!(
        lens,
        CameraLens::Orthographic {
            half_width: hw,
            half_height: hh
        }
    );
    let cam = camera(Vec3::new(-20.0, 8.0, 5.0), Vec3::new(10.0, 0.0, -3.0));
    let views = cascade_views(cam, lens, NEAR, DIST, light(), SIDE, &scene());
    let mut n = NEAR;
    for v in &views {
        // The slice is a box: ±hw by ±hh at every depth.
        for i in 0..=4 {
            let d = n + (v.split_far - n) * i as f32 / 4.0;
            for (u, w) in [
                (-1.0, -1.0),
                (1.0, -1.0),
                (-1.0, 1.0),
                (1.0, 1.0),
                (0.3, -0.2),
            ] {
                let p = cam.transform_point3(Vec3::new(u * hw, w * hh, -d));
                let q = v.ndc(p);
                assert!(q.x.abs() <= 1.0 && q.y.abs() <= 1.0, "{q}");
                assert!(q.z >= 0.0 && q.z <= 1.0, "{q}");
            }
        }
        // And no larger than the box's bounding sphere, a texel either side.
        let half_depth = (v.split_far - n) * 0.5;
        let radius = (half_depth * half_depth + hw * hw + hh * hh).sqrt();
        let half = v.texel_world * SIDE as f32 * 0.5;
        assert!(
            half <= radius * 1.01 + 2.0 * v.texel_world,
            "{half} against {radius}"
        );
        n = v.split_far;
    }
}
