//! Blended draws ordered on the GPU (`blended_order` keys, the bitonic sort, one multi-draw
//! through one pipeline that culls no face) render as the CPU orders them: a stack of tinted
//! glass boxes and panes, single- and double-sided, some mirrored, seen by perspective and
//! orthographic cameras, against the same scene on a device without
//! `INDIRECT_FIRST_INSTANCE`, where the renderer sorts the blended draws on the CPU
//! (`ViewDraws::blended_back_to_front`) and draws each with a pipeline of its sidedness.

use glam::{Mat4, Quat, Vec3, Vec4};
use renderer::GpuContext;
use renderer::demo::{Rng, procedural_lights};
use renderer::frame::{FrameCamera, RenderPath};
use renderer::scene::procedural::{SceneBuilder, box_primitive};
use renderer::scene::{Aabb, AlphaMode, Material, Scene};
use tests::frames::{largest_difference, render_frame_from};
use tests::gpu::gpu_test;

use super::{SIZE, config};

/// An opaque floor and wall, then 90 blended boxes and panes in overlapping rows: four glass
/// tints, two of them double-sided, a quarter of the instances mirrored.
fn glass_stack() -> Scene {
    let mut b = SceneBuilder::new();
    let floor = b.material("floor", Vec3::new(0.5, 0.45, 0.4), 0.7);
    b.cuboid(
        Vec3::new(-30.0, -0.1, -40.0),
        Vec3::new(30.0, 0.0, 10.0),
        floor,
    );
    b.cuboid(
        Vec3::new(-30.0, 0.0, -41.0),
        Vec3::new(30.0, 20.0, -40.0),
        floor,
    );
    let glass = [
        (Vec4::new(0.9, 0.2, 0.2, 0.45), false),
        (Vec4::new(0.2, 0.8, 0.3, 0.35), true),
        (Vec4::new(0.2, 0.3, 0.9, 0.5), false),
        (Vec4::new(0.9, 0.8, 0.2, 0.3), true),
    ]
    .map(|(tint, double_sided)| {
        b.add_material(Material {
            name: format!("glass {tint}"),
            base_color: tint,
            roughness: 0.2,
            alpha_mode: AlphaMode::Blend,
            double_sided,
            ..Material::gltf_default()
        })
    });
    let shapes: Vec<usize> = glass
        .iter()
        .enumerate()
        .flat_map(|(i, &m)| {
            let double_sided = i % 2 == 1;
            let cube = box_primitive(Vec3::splat(-1.0), Vec3::ONE, m, double_sided);
            let pane = box_primitive(
                Vec3::new(-1.5, -1.0, 0.0),
                Vec3::new(1.5, 1.0, 0.0),
                m,
                double_sided,
            );
            [b.mesh("glass box", cube), b.mesh("glass pane", pane)]
        })
        .collect();
    let mut rng = Rng::new(17);
    for i in 0..90 {
        let at = Vec3::new(
            rng.range(-12.0, 12.0),
            rng.range(0.5, 7.0),
            rng.range(-30.0, 2.0),
        );
        let turn = Quat::from_rotation_y(rng.range(-1.2, 1.2));
        let scale = if i % 4 == 0 {
            Vec3::new(-1.0, 1.0, 1.0)
        } else {
            Vec3::ONE
        } * rng.range(0.6, 1.6);
        let shape = shapes[(rng.next_u64() % shapes.len() as u64) as usize];
        b.place(
            shape,
            Mat4::from_scale_rotation_translation(scale, turn, at),
        );
    }
    b.build()
}

/// The cameras: into the stack from in front, from its side (some glass behind the eye and
/// some off screen), and an orthographic view down the rows.
fn cameras() -> [FrameCamera; 3] {
    let aspect = SIZE.0 as f32 / SIZE.1 as f32;
    let look = |eye: Vec3, at: Vec3| {
        FrameCamera::look_at(eye, at, Vec3::Y, 55f32.to_radians(), aspect, (0.1, 200.0))
    };
    let (eye, at) = (Vec3::new(6.0, 9.0, 12.0), Vec3::new(0.0, 2.0, -14.0));
    let ortho_from = glam::camera::rh::view::look_at_mat4(eye, at, Vec3::Y).inverse();
    [
        look(Vec3::new(0.0, 4.0, 14.0), Vec3::new(0.0, 3.0, -15.0)),
        look(Vec3::new(-16.0, 3.0, -14.0), Vec3::new(10.0, 4.0, -10.0)),
        FrameCamera::orthographic(ortho_from, (14.0, 14.0 / aspect), (0.5, 80.0)),
    ]
}

/// The same adapter opened without `INDIRECT_FIRST_INSTANCE`: the renderer orders blended
/// draws on the CPU there.
pub(super) fn without_indirect_first_instance(gpu: &GpuContext) -> GpuContext {
    let (features, limits) =
        renderer::gpu::requirements::for_adapter(gpu.adapter()).expect("requirements");
    let (device, queue) =
        pollster::block_on(gpu.adapter().request_device(&wgpu::DeviceDescriptor {
            label: Some("device without indirect first instance"),
            required_features: features - wgpu::Features::INDIRECT_FIRST_INSTANCE,
            required_limits: limits,
            ..Default::default()
        }))
        .expect("a device without indirect first instance");
    GpuContext::from_parts(gpu.instance().clone(), gpu.adapter().clone(), device, queue)
        .expect("the device has the renderer's limits")
}

#[test]
fn blended_draws_ordered_on_the_gpu_render_as_the_cpu_orders_them() {
    let scene = glass_stack();
    let region = Aabb {
        min: Vec3::new(-14.0, 0.5, -32.0),
        max: Vec3::new(14.0, 8.0, 4.0),
    };
    let lights = procedural_lights(region, 48, 5, 6.0, 14.0);
    gpu_test(|gpu| {
        let cpu_ordered = without_indirect_first_instance(gpu);
        // Forward+ and, over a deferred image, the TBDR path's forward pass; one camera each.
        let paths = [
            (RenderPath::Tiled, 4),
            (RenderPath::Tbdr, 1),
            (RenderPath::Tiled, 1),
        ];
        for (i, (camera, (path, msaa))) in cameras().iter().zip(paths).enumerate() {
            let settings = config(path, msaa, true);
            let sorted = render_frame_from(gpu, &scene, settings, &lights, camera);
            let listed = render_frame_from(&cpu_ordered, &scene, settings, &lights, camera);
            let draws = sorted.report.scene_draws.expect("reported");
            assert_eq!(draws.blended, 90, "every glass instance is a blended draw");
            let worst = largest_difference(&sorted.rgba, &listed.rgba);
            assert!(
                worst <= 1,
                "camera {i}, {path:?}: the GPU's blended order differs from the CPU's by {worst}"
            );
        }
    });
}

/// `mesh` with only the triangles whose outward normal faces `eye` where `world_from_mesh`
/// puts them (the vertices, hence the bounds and the draw's sort key, kept).
fn front_faces_only(
    mesh: &renderer::scene::Mesh,
    world_from_mesh: Mat4,
    eye: Vec3,
) -> renderer::scene::Mesh {
    let normal_from_mesh = world_from_mesh.inverse().transpose();
    let mut out = mesh.clone();
    for p in &mut out.primitives {
        let faces_eye = |t: &[u32]| {
            let a = world_from_mesh.transform_point3(p.positions[t[0] as usize]);
            let n = normal_from_mesh.transform_vector3(p.normals[t[0] as usize]);
            n.dot(eye - a) > 0.0
        };
        p.indices = p
            .indices
            .chunks(3)
            .filter(|t| faces_eye(t))
            .flatten()
            .copied()
            .collect();
    }
    out
}

#[test]
fn blended_single_sided_draws_show_their_front_faces_only_mirrored_or_not() {
    // A wall, and two single-sided glass boxes turned to show three faces each: one as
    // modelled, one mirrored (its front faces wind clockwise).
    let mut b = SceneBuilder::new();
    let wall = b.material("wall", Vec3::new(0.8, 0.8, 0.75), 0.6);
    b.cuboid(
        Vec3::new(-20.0, -5.0, -12.0),
        Vec3::new(20.0, 15.0, -11.0),
        wall,
    );
    let glass = b.add_material(Material {
        name: "glass".into(),
        base_color: Vec4::new(0.3, 0.5, 0.9, 0.4),
        roughness: 0.3,
        alpha_mode: AlphaMode::Blend,
        ..Material::gltf_default()
    });
    let cube = b.mesh(
        "glass box",
        box_primitive(Vec3::splat(-1.0), Vec3::ONE, glass, false),
    );
    let turn = Quat::from_rotation_y(0.6) * Quat::from_rotation_x(0.4);
    let placed = [
        Mat4::from_scale_rotation_translation(Vec3::splat(1.5), turn, Vec3::new(-3.0, 2.0, -4.0)),
        Mat4::from_scale_rotation_translation(
            Vec3::new(-1.5, 1.5, 1.5),
            turn,
            Vec3::new(3.0, 2.0, -4.0),
        ),
    ];
    for world in placed {
        b.place(cube, world);
    }
    let scene = b.build();
    let eye = Vec3::new(0.0, 4.0, 8.0);
    let aspect = SIZE.0 as f32 / SIZE.1 as f32;
    let camera = FrameCamera::look_at(
        eye,
        Vec3::new(0.0, 2.0, -4.0),
        Vec3::Y,
        50f32.to_radians(),
        aspect,
        (0.1, 100.0),
    );
    // The reference: each box's mesh cut down to the faces turned to the eye.
    let mut reference = scene.clone();
    for (i, world) in placed.iter().enumerate() {
        reference
            .meshes
            .push(front_faces_only(&scene.meshes[cube], *world, eye));
        reference.instances[1 + i].mesh = reference.meshes.len() - 1;
        let kept = reference
            .meshes
            .last()
            .map(|m| m.primitives[0].indices.len());
        assert_eq!(kept, Some(18), "box {i} shows three faces to the eye");
    }
    let mut bare_wall = scene.clone();
    bare_wall.instances.truncate(1);
    let region = Aabb {
        min: Vec3::new(-8.0, 0.0, -8.0),
        max: Vec3::new(8.0, 6.0, 4.0),
    };
    let lights = procedural_lights(region, 16, 3, 6.0, 12.0);
    gpu_test(|gpu| {
        for (path, msaa) in [(RenderPath::Tiled, 4), (RenderPath::Tbdr, 1)] {
            let settings = config(path, msaa, true);
            let boxes = render_frame_from(gpu, &scene, settings, &lights, &camera);
            let faces = render_frame_from(gpu, &reference, settings, &lights, &camera);
            let worst = largest_difference(&boxes.rgba, &faces.rgba);
            assert!(
                worst <= 1,
                "{path:?}: blended boxes differ from their front faces by {worst}"
            );
            let wall = render_frame_from(gpu, &bare_wall, settings, &lights, &camera);
            let glass = largest_difference(&boxes.rgba, &wall.rgba);
            assert!(glass > 20, "{path:?}: the glass shows ({glass})");
        }
    });
}
