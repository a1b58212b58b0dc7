//! The shadow tests' scene: a floor, a box and a pillar, lit by one spot, one point or one
//! directional light, seen from above; and an independent CPU ray cast that says which floor
//! points each light reaches.

use glam::{Vec3, camera::rh};
use renderer::frame::FrameCamera;
use renderer::scene::procedural::SceneBuilder;
use renderer::scene::{Aabb, LightKind, Scene, SceneLight};

/// Top of the floor slab.
pub const FLOOR_Y: f32 = 0.0;
/// Half the floor's side.
pub const FLOOR_HALF: f32 = 6.0;

/// The occluders, in world space: the box and the pillar.
pub fn occluders() -> [Aabb; 2] {
    [
        Aabb {
            min: Vec3::new(-2.0, 0.0, -1.0),
            max: Vec3::new(-0.5, 1.2, 0.5),
        },
        Aabb {
            min: Vec3::new(1.5, 0.0, 0.5),
            max: Vec3::new(2.1, 3.0, 1.1),
        },
    ]
}

/// The floor, the box and the pillar (instances 0, 1 and 2).
pub fn scene() -> Scene {
    let mut b = SceneBuilder::new();
    let grey = b.material("floor", Vec3::splat(0.6), 0.9);
    let white = b.material("occluder", Vec3::splat(0.8), 0.6);
    b.cuboid(
        Vec3::new(-FLOOR_HALF, -0.2, -FLOOR_HALF),
        Vec3::new(FLOOR_HALF, FLOOR_Y, FLOOR_HALF),
        grey,
    );
    for o in occluders() {
        b.cuboid(o.min, o.max, white);
    }
    b.build()
}

/// The three test lights: a spot, a point and a directional light, each casting a shadow.
pub fn lights() -> [SceneLight; 3] {
    let spot_at = Vec3::new(-3.5, 4.0, 2.5);
    [
        SceneLight {
            kind: LightKind::Spot {
                inner_cone: 0.6,
                outer_cone: 0.9,
            },
            position: spot_at,
            direction: (Vec3::new(-0.5, 0.0, 0.0) - spot_at).normalize(),
            color: Vec3::ONE,
            intensity: 60.0,
            range: Some(14.0),
            casts_shadow: true,
        },
        SceneLight {
            kind: LightKind::Point,
            position: Vec3::new(0.6, 2.2, -0.4),
            direction: Vec3::NEG_Y,
            color: Vec3::ONE,
            intensity: 12.0,
            range: Some(12.0),
            casts_shadow: true,
        },
        SceneLight {
            kind: LightKind::Directional,
            position: Vec3::ZERO,
            direction: Vec3::new(0.45, -1.0, 0.3).normalize(),
            color: Vec3::ONE,
            intensity: 3.0,
            range: None,
            casts_shadow: true,
        },
    ]
}

/// The camera looking down at the floor from above and to the side.
pub fn camera(aspect: f32) -> FrameCamera {
    let eye = Vec3::new(0.0, 9.0, 7.0);
    let (near, far) = (0.1, 60.0);
    FrameCamera {
        view: rh::view::look_at_mat4(eye, Vec3::ZERO, Vec3::Y),
        projection: rh::proj::directx::perspective(45f32.to_radians(), aspect, near, far),
        eye,
        near,
        far,
    }
}

/// Whether the segment from `a` to `b` passes through `boxes` (slab test).
pub fn segment_blocked(a: Vec3, b: Vec3, boxes: &[Aabb]) -> bool {
    let d = b - a;
    boxes.iter().any(|bx| {
        let (mut t0, mut t1) = (1.0e-4_f32, 1.0_f32 - 1.0e-4);
        for axis in 0..3 {
            let (o, v) = (a[axis], d[axis]);
            if v.abs() < 1.0e-9 {
                if o < bx.min[axis] || o > bx.max[axis] {
                    return false;
                }
                continue;
            }
            let (mut n, mut f) = ((bx.min[axis] - o) / v, (bx.max[axis] - o) / v);
            if n > f {
                std::mem::swap(&mut n, &mut f);
            }
            t0 = t0.max(n);
            t1 = t1.min(f);
            if t0 > t1 {
                return false;
            }
        }
        true
    })
}

/// Whether `light` reaches floor point `p` unblocked by the occluders.
pub fn reaches(light: &SceneLight, p: Vec3) -> bool {
    let from = match light.kind {
        LightKind::Directional => p - light.direction * 100.0,
        _ => light.position,
    };
    !segment_blocked(p, from, &occluders())
}

/// The floor point seen through pixel `(x, y)` of a `w`×`h` frame, if the camera sees the
/// floor's top there without an occluder in front.
pub fn floor_point(camera: &FrameCamera, x: u32, y: u32, w: u32, h: u32) -> Option<Vec3> {
    let ndc = glam::Vec2::new(
        (x as f32 + 0.5) / w as f32 * 2.0 - 1.0,
        1.0 - (y as f32 + 0.5) / h as f32 * 2.0,
    );
    let inv = (camera.projection * camera.view).inverse();
    let far = inv.project_point3(ndc.extend(0.5));
    let dir = (far - camera.eye).normalize();
    if dir.y >= -1.0e-6 {
        return None;
    }
    let t = (FLOOR_Y - camera.eye.y) / dir.y;
    let p = camera.eye + dir * t;
    let on_floor = p.x.abs() < FLOOR_HALF && p.z.abs() < FLOOR_HALF;
    (on_floor && !segment_blocked(camera.eye, p, &occluders())).then_some(p)
}
