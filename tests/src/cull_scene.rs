//! Seeded synthetic culling scenes: an analytically ray-cast depth buffer with discontinuities
//! (floor, a near wall in front of far geometry, spheres, sky) and lights covering the cases
//! that break culling (behind the camera, straddling the near plane, huge, zero radius, many in
//! one tile).

use glam::{Mat4, Quat, Vec3, camera::rh};
use renderer::culling::reference::{CullCamera, DepthBuffer, LightSphere};
use renderer::decals::OrientedBox;

pub use renderer::demo::Rng;

/// Camera, depth buffer and world-space lights of one test scene.
#[derive(Debug, Clone)]
pub struct CullScene {
    pub camera: CullCamera,
    pub depth: DepthBuffer,
    pub lights: Vec<LightSphere>,
}

impl CullScene {
    /// World-space boxes in view space, as the reference's box culling takes them.
    pub fn boxes_view(&self, boxes: &[OrientedBox]) -> Vec<OrientedBox> {
        boxes
            .iter()
            .map(|b| b.transformed(self.camera.view))
            .collect()
    }

    /// The lights in view space, as the culling methods take them.
    pub fn lights_view(&self) -> Vec<LightSphere> {
        self.lights
            .iter()
            .map(|l| l.to_view(self.camera.view))
            .collect()
    }
}

pub const NEAR: f32 = 0.1;
pub const FAR: f32 = 100.0;

/// Builds the scene at `width`×`height` with `samples` per pixel and `random_lights` random lights
/// (plus the fixed special cases).
pub fn scene(seed: u64, width: u32, height: u32, samples: u32, random_lights: usize) -> CullScene {
    scene_with_radii(seed, width, height, samples, random_lights, 0.2, 3.0)
}

/// [`scene`] with the random lights' radii drawn from `[min_radius, max_radius)`.
pub fn scene_with_radii(
    seed: u64,
    width: u32,
    height: u32,
    samples: u32,
    random_lights: usize,
    min_radius: f32,
    max_radius: f32,
) -> CullScene {
    let view = rh::view::look_at_mat4(Vec3::new(0.0, 2.0, 8.0), Vec3::new(0.0, 1.0, 0.0), Vec3::Y);
    // wgpu's clip space is Direct3D's: y up, depth 0..1.
    let projection =
        rh::proj::directx::perspective(60f32.to_radians(), width as f32 / height as f32, NEAR, FAR);
    let camera = CullCamera {
        view,
        projection,
        width,
        height,
    };
    let depth = ray_cast_depth(&camera, samples);
    let mut rng = Rng::new(seed);
    let mut lights: Vec<LightSphere> = (0..random_lights)
        .map(|_| LightSphere {
            center: Vec3::new(
                rng.range(-12.0, 12.0),
                rng.range(-1.0, 6.0),
                rng.range(-30.0, 10.0),
            ),
            radius: rng.range(min_radius, max_radius),
        })
        .collect();
    let eye = Vec3::new(0.0, 2.0, 8.0);
    lights.extend([
        // Behind the camera, clear of the near plane.
        LightSphere {
            center: eye + Vec3::new(0.0, 0.0, 3.0),
            radius: 1.0,
        },
        // Straddling the near plane, lighting the near wall.
        LightSphere {
            center: eye + Vec3::new(0.5, -0.5, 0.0),
            radius: 2.5,
        },
        // Huge: covers everything.
        LightSphere {
            center: Vec3::new(0.0, 0.0, -10.0),
            radius: 500.0,
        },
        // Zero radius, in front of the camera.
        LightSphere {
            center: Vec3::new(0.0, 0.5, 2.0),
            radius: 0.0,
        },
    ]);
    // Many small lights crowding one spot on the floor: one tile's overflow case.
    for k in 0..64 {
        let a = k as f32 * 0.1;
        lights.push(LightSphere {
            center: Vec3::new(0.05 * a.cos(), 0.02, 0.05 * a.sin()),
            radius: 0.3,
        });
    }
    CullScene {
        camera,
        depth,
        lights,
    }
}

/// `random` seeded decal boxes on and around the scene's surfaces (rotated every way, 0.05 to
/// 4 units a side, some long and thin so their bounding spheres are much larger than they are),
/// plus the awkward ones: tiny, huge, behind the camera, straddling the near plane, and `crowd`
/// boxes overlapping one spot on the floor.
pub fn decal_boxes(seed: u64, random: usize, crowd: usize) -> Vec<OrientedBox> {
    let mut rng = Rng::new(seed ^ 0xDEC4_1500);
    let boxed = |center: Vec3, rotation: Quat, size: Vec3| {
        let m = Mat4::from_scale_rotation_translation(size, rotation, center);
        OrientedBox::from_matrix(m).expect("a valid box")
    };
    let mut boxes: Vec<OrientedBox> = (0..random)
        .map(|k| {
            let center = Vec3::new(
                rng.range(-12.0, 12.0),
                rng.range(-0.5, 4.0),
                rng.range(-30.0, 8.0),
            );
            let axis = Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            let rotation = Quat::from_axis_angle(axis.normalize_or(Vec3::Y), rng.range(0.0, 6.3));
            let mut size = Vec3::new(
                rng.range(0.05, 4.0),
                rng.range(0.05, 4.0),
                rng.range(0.05, 2.0),
            );
            if k % 5 == 0 {
                // Long and thin: a plank whose sphere covers far more than the box.
                size = Vec3::new(rng.range(4.0, 10.0), 0.1, 0.1);
            }
            boxed(center, rotation, size)
        })
        .collect();
    let eye = Vec3::new(0.0, 2.0, 8.0);
    boxes.extend([
        boxed(
            Vec3::new(0.3, 0.0, 1.0),
            Quat::from_rotation_y(0.4),
            Vec3::splat(1.0e-3),
        ),
        boxed(
            Vec3::new(0.0, 0.0, -10.0),
            Quat::from_rotation_x(0.3),
            Vec3::splat(200.0),
        ),
        boxed(
            eye + Vec3::new(0.0, 0.0, 3.0),
            Quat::IDENTITY,
            Vec3::splat(1.0),
        ),
        boxed(
            eye + Vec3::new(0.4, -0.4, 0.0),
            Quat::from_rotation_z(0.7),
            Vec3::new(2.0, 1.0, 1.0),
        ),
    ]);
    for k in 0..crowd {
        let a = k as f32 * 0.37;
        boxes.push(boxed(
            Vec3::new(0.1 * a.cos(), 0.0, 0.1 * a.sin()),
            Quat::from_rotation_y(a),
            Vec3::new(0.6, 0.6, 0.3),
        ));
    }
    boxes
}

/// Ray-casts the scene's surfaces for every sample and stores wgpu depth (1.0 = sky).
fn ray_cast_depth(camera: &CullCamera, samples: u32) -> DepthBuffer {
    let mut depth = DepthBuffer {
        width: camera.width,
        height: camera.height,
        samples,
        depth: vec![1.0; (camera.width * camera.height * samples) as usize],
    };
    let to_world = camera.view.inverse();
    let origin = to_world.transform_point3(Vec3::ZERO);
    for y in 0..camera.height {
        for x in 0..camera.width {
            for s in 0..samples {
                let (ox, oy) = depth.sample_offset(s);
                let (nx, ny) = camera.pixel_to_ndc(x as f32 + ox, y as f32 + oy);
                let far_point = camera.unproject(nx, ny, 1.0);
                let dir = to_world.transform_vector3(far_point).normalize();
                if let Some(t) = nearest_hit(origin, dir) {
                    let p_view = camera.view.transform_point3(origin + dir * t);
                    let clip = camera.projection * p_view.extend(1.0);
                    let z = clip.z / clip.w;
                    if (0.0..1.0).contains(&z) {
                        let i = ((y * camera.width + x) * samples + s) as usize;
                        depth.depth[i] = z;
                    }
                }
            }
        }
    }
    depth
}

/// Distance along the ray to the nearest surface, if any.
fn nearest_hit(o: Vec3, d: Vec3) -> Option<f32> {
    let mut best: Option<f32> = None;
    let mut keep = |t: f32| {
        if t > 1e-4 && best.is_none_or(|b| t < b) {
            best = Some(t);
        }
    };
    // Floor y = 0, out to 40 units.
    if d.y < -1e-6 {
        let t = -o.y / d.y;
        let p = o + d * t;
        if p.x.abs() < 40.0 && p.z > -40.0 && p.z < 20.0 {
            keep(t);
        }
    }
    // A near wall at z = 4 covering the left part of the view: a sharp depth discontinuity.
    if d.z.abs() > 1e-6 {
        let t = (4.0 - o.z) / d.z;
        let p = o + d * t;
        if (-6.0..-1.0).contains(&p.x) && (0.0..3.0).contains(&p.y) {
            keep(t);
        }
    }
    // A far back wall at z = -35 with a gap of sky above it.
    if d.z.abs() > 1e-6 {
        let t = (-35.0 - o.z) / d.z;
        let p = o + d * t;
        if p.x.abs() < 30.0 && (0.0..8.0).contains(&p.y) {
            keep(t);
        }
    }
    // Spheres at several depths.
    for (c, r) in [
        (Vec3::new(2.0, 1.0, 0.0), 1.0),
        (Vec3::new(-1.0, 0.5, -6.0), 0.5),
        (Vec3::new(4.0, 2.0, -15.0), 2.0),
    ] {
        let oc = o - c;
        let b = oc.dot(d);
        let disc = b * b - (oc.length_squared() - r * r);
        if disc >= 0.0 {
            keep(-b - disc.sqrt());
        }
    }
    best
}
