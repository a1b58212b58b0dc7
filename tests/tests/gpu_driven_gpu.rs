//! Scenes at an engine's scale, drawn from shared geometry buffers through GPU-culled indirect
//! batches: on a generated city with occluders, the culled Forward+ paths equal naive forward at
//! MSAA 1 and 4 (the deferred paths are compared in `tbdr_gpu`); culling on equals culling off,
//! pixel for pixel, over a scripted camera flight (the first frame, a fast turn, a walk that
//! brings buildings in from off screen) while culling does leave draws out; and instances moved
//! by handle (into view, out of it, mirrored) render the same as a city built with them there;
//! instances added and removed by handle likewise (`edits`), and meshes, materials and images
//! added at run time (`assets`) and removed, their room taken by later ones (`removal`); material textures reached by index through the material atlas
//! sample as the hardware sampler does (`atlas`); occlusion culling hides what a wall hides and nothing visible
//! (`occlusion`); blended draws ordered back to front on the GPU render as the CPU orders them
//! (`blended`); shadow casters culled per atlas region on the GPU draw the atlas the CPU's
//! caster lists draw (`shadows`).

#[path = "gpu_driven_gpu/assets.rs"]
mod assets;
#[path = "gpu_driven_gpu/atlas.rs"]
mod atlas;
#[path = "gpu_driven_gpu/blended.rs"]
mod blended;
#[path = "gpu_driven_gpu/edits.rs"]
mod edits;
#[path = "gpu_driven_gpu/occlusion.rs"]
mod occlusion;
#[path = "gpu_driven_gpu/removal.rs"]
mod removal;
#[path = "gpu_driven_gpu/shadows.rs"]
mod shadows;

use glam::{Mat4, Vec3};
use renderer::GpuContext;
use renderer::demo::procedural_lights;
use renderer::frame::default_camera;
use renderer::frame::{FrameCamera, RenderPath, Renderer, RendererConfig};
use renderer::scene::procedural::{BuiltinScene, builtin};
use renderer::scene::{Scene, SceneLight};
use tests::frames::{largest_difference, render_frame_from, render_one_frame};
use tests::gpu::gpu_test;

const SIZE: (u32, u32) = (192, 108);

fn city(instances: usize) -> BuiltinScene {
    builtin(&format!("city:{instances}"))
        .expect("a valid name")
        .expect("a built-in scene")
}

fn street_lights(city: &BuiltinScene) -> Vec<SceneLight> {
    let (min, max) = city.light_radii;
    procedural_lights(city.light_region, 256, 11, min, max)
}

fn config(path: RenderPath, msaa: u32, cull_draws: bool) -> RendererConfig {
    RendererConfig {
        width: SIZE.0,
        height: SIZE.1,
        msaa,
        path,
        tile: 16,
        cull_draws,
        // Occlusion culling on every city, the smallest included.
        occlusion_min_draws: 0,
        ..Default::default()
    }
}

fn street_camera(scene: &Scene) -> FrameCamera {
    default_camera(scene, SIZE.0 as f32 / SIZE.1 as f32)
}

#[test]
fn the_city_culled_equals_naive_at_msaa_1_and_4() {
    let city = city(1_500);
    let lights = street_lights(&city);
    let camera = street_camera(&city.scene);
    gpu_test(|gpu| {
        for msaa in [1, 4] {
            let frame = |path| {
                let f =
                    render_frame_from(gpu, &city.scene, config(path, msaa, true), &lights, &camera);
                let draws = f
                    .report
                    .scene_draws
                    .expect("the scene's draws are reported");
                let all = draws.draws + draws.blended;
                assert_eq!(all, 1_500, "{path:?}: one draw per instance");
                f.rgba
            };
            let naive = frame(RenderPath::Naive);
            for path in [
                RenderPath::NaivePrez,
                RenderPath::Tiled,
                RenderPath::Depth25,
                RenderPath::Clustered,
            ] {
                let worst = largest_difference(&naive, &frame(path));
                assert!(
                    worst <= 1,
                    "{path:?}, MSAA {msaa}: differs from naive by {worst}"
                );
            }
        }
    });
}

/// The flight: the street camera, a quarter turn in one frame, then a walk down the street with
/// the camera swinging, so buildings enter from the frame's edges and from behind corners.
fn flight(start: &FrameCamera) -> Vec<FrameCamera> {
    let world_from_view = start.view.inverse();
    let eye = start.eye;
    let forward = -world_from_view.z_axis.truncate();
    let aspect = SIZE.0 as f32 / SIZE.1 as f32;
    let look = |eye: Vec3, yaw: f32| {
        let dir = Mat4::from_rotation_y(yaw).transform_vector3(forward);
        FrameCamera::look_at(
            eye,
            eye + dir,
            Vec3::Y,
            60f32.to_radians(),
            aspect,
            (0.1, 2_000.0),
        )
    };
    let mut frames = vec![*start, look(eye, std::f32::consts::FRAC_PI_2)];
    for step in 0..4 {
        let t = step as f32;
        frames.push(look(eye + forward * (12.0 * t), 0.6 * (t - 1.5)));
    }
    frames
}

/// Renders every camera of `cameras` with one renderer, reading each frame back.
fn fly(
    gpu: &GpuContext,
    scene: &Scene,
    lights: &[SceneLight],
    config: RendererConfig,
    cameras: &[FrameCamera],
) -> Vec<(Vec<u8>, Option<renderer::frame_data::SceneDrawReport>)> {
    let mut renderer = Renderer::new(gpu, config).expect("renderer");
    renderer.prepare_scene(scene).expect("the city fits");
    renderer.set_lights(lights).expect("lights fit");
    cameras
        .iter()
        .map(|camera| {
            let f = render_one_frame(gpu, &mut renderer, camera);
            (f.rgba, f.report.scene_draws)
        })
        .collect()
}

#[test]
fn culling_on_equals_culling_off_over_a_camera_flight() {
    let city = city(3_000);
    let lights = street_lights(&city);
    let cameras = flight(&street_camera(&city.scene));
    gpu_test(|gpu| {
        let features = gpu.device().features();
        assert!(
            features.contains(wgpu::Features::MULTI_DRAW_INDIRECT_COUNT),
            "lavapipe and every Vulkan GPU draw with GPU-written counts"
        );
        for (path, msaa) in [
            (RenderPath::Naive, 1),
            (RenderPath::Tiled, 4),
            (RenderPath::Tbdr, 4),
        ] {
            let on = fly(
                gpu,
                &city.scene,
                &lights,
                config(path, msaa, true),
                &cameras,
            );
            let off = fly(
                gpu,
                &city.scene,
                &lights,
                config(path, msaa, false),
                &cameras,
            );
            for (i, ((culled, report), (all, _))) in on.iter().zip(&off).enumerate() {
                let worst = largest_difference(culled, all);
                assert_eq!(
                    worst, 0,
                    "{path:?}, frame {i}: culling changed a pixel by {worst}"
                );
                let report = report.expect("reported");
                // Lavapipe draws with GPU-written counts, so the culled lists are packed.
                assert!(
                    report.packed,
                    "{path:?}, frame {i}: the culled slots were not packed"
                );
                // The count arrives a frame or more late; the last frames have one.
                if let Some(visible) = report.visible {
                    assert!(
                        visible < report.draws / 2,
                        "{path:?}, frame {i}: culling kept {visible} of {} draws",
                        report.draws
                    );
                }
            }
            assert!(
                on.iter().any(|(_, r)| r.and_then(|r| r.visible).is_some()),
                "{path:?}: no culled count came back"
            );
        }
    });
}

#[test]
fn instances_moved_by_handle_render_as_a_city_built_with_them_there() {
    let base = city(1_200);
    let lights = street_lights(&base);
    let camera = street_camera(&base.scene);
    let eye = camera.eye;
    // Two towers: the one furthest behind the camera (culled where it stands) into the street
    // in front of it and mirrored (negative scale: its draws change pipeline), and the one
    // nearest a point down the street out of view.
    let towers: Vec<usize> = base
        .scene
        .instances
        .iter()
        .enumerate()
        .filter(|(_, i)| base.scene.meshes[i.mesh].name == "tower")
        .map(|(k, _)| k)
        .collect();
    let down_the_street = eye + Vec3::new(60.0, 0.0, 0.0);
    let distance = |k: usize| {
        let at = base.scene.instances[k].world_from_mesh.w_axis.truncate();
        at.distance(down_the_street)
    };
    let seen = towers
        .iter()
        .copied()
        .min_by(|&a, &b| distance(a).total_cmp(&distance(b)))
        .expect("towers");
    let x = |k: usize| base.scene.instances[k].world_from_mesh.w_axis.x;
    let far = towers
        .iter()
        .copied()
        .min_by(|&a, &b| x(a).total_cmp(&x(b)))
        .expect("towers");
    assert!(
        x(far) < eye.x - 100.0,
        "the tower must start behind the camera"
    );
    let into_the_street = Mat4::from_scale_rotation_translation(
        Vec3::new(-4.0, 9.0, 4.0),
        glam::Quat::IDENTITY,
        eye + Vec3::new(30.0, -1.7, -2.5),
    );
    let moves = [
        (far, into_the_street),
        (seen, Mat4::from_translation(Vec3::new(0.0, -500.0, 0.0))),
    ];
    let mut built = base.scene.clone();
    for &(i, m) in &moves {
        built.instances[i].world_from_mesh = m;
    }
    gpu_test(|gpu| {
        for path in [RenderPath::Tiled, RenderPath::Tbdr] {
            let config = config(path, 4, true);
            let mut renderer = Renderer::new(gpu, config).expect("renderer");
            renderer.prepare_scene(&base.scene).expect("the city fits");
            renderer.set_lights(&lights).expect("lights fit");
            let before = render_one_frame(gpu, &mut renderer, &camera).rgba;
            for &(i, m) in &moves {
                let handle = renderer.scene_instance(i).expect("an instance");
                renderer
                    .set_instance_transform(handle, m)
                    .expect("a live instance");
            }
            let moved = render_one_frame(gpu, &mut renderer, &camera).rgba;
            let expected = render_frame_from(gpu, &built, config, &lights, &camera).rgba;
            let worst = largest_difference(&moved, &expected);
            assert_eq!(worst, 0, "{path:?}: the moved city differs by {worst}");
            assert!(
                largest_difference(&before, &moved) > 32,
                "{path:?}: the moves must show in the frame"
            );
        }
    });
}
