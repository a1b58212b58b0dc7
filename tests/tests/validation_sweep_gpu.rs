//! Every render path under the Khronos validation layer, full frames: each path at MSAA 1 and
//! 4, plain and (the culled paths, which have lists to scalarize) scalarized, on the demo scene (the courtyard with its procedural decals,
//! shadowed lights and particles, as `cargo xtask demo` draws it) and on a shared glTF scene
//! (LightsPunctualLamp, with its own lights). The harness (`tests::gpu`) fails a test on any
//! layer error or warning; this sweep is what makes that hold for every combination rather than
//! for the ones other tests happen to draw.
//!
//! Every frame, plain or scalarized, is counted and checked lit, and each scalarized frame is
//! compared with the plain frame of its path and MSAA: scalarizing loads a list entry once per
//! subgroup instead of once per invocation, the same lights in the same order, so the two are
//! equal (measured: largest channel difference 0 on lavapipe, subgroup size 8). On a device
//! without subgroups nothing is skipped: each scalarized configuration must be refused with
//! `RenderError::Config(ConfigError::NoSubgroup)`; the last test opens such a device (the same adapter without the
//! SUBGROUP feature) and checks exactly that, so the branch runs on every machine.

use renderer::decals::{DecalSet, procedural};
use renderer::demo::scatter_decals;
use renderer::demo::{courtyard_look, light_space, pick_shadowed, procedural_lights};
use renderer::frame::ConfigError;
use renderer::frame::default_camera;
use renderer::frame::{RenderPath, RendererConfig};
use renderer::frame_data::RenderError;
use renderer::particles::{WARMUP_STEPS, builtin_system};
use renderer::scene::{Scene, SceneLight};
use renderer::{GpuContext, frame::Renderer};
use tests::frames::{largest_difference, render_one_frame};
use tests::gpu::gpu_test;

const WIDTH: u32 = 96;
const HEIGHT: u32 = 64;

struct Stage {
    name: &'static str,
    scene: Scene,
    lights: Vec<SceneLight>,
    decals: DecalSet,
    particles: u32,
    look: fn(RendererConfig) -> RendererConfig,
}

fn demo_stage() -> Stage {
    let scene = renderer::scene::procedural::courtyard();
    let (region, (rmin, rmax)) = light_space(&scene, true);
    let mut lights = procedural_lights(region, 256, 1, rmin, rmax);
    let camera = default_camera(&scene, WIDTH as f32 / HEIGHT as f32);
    pick_shadowed(&mut lights, &camera, HEIGHT as f32, 8);
    let materials = procedural::materials();
    let decals = scatter_decals(&scene, 32, materials.len(), 1);
    Stage {
        name: "demo courtyard",
        lights,
        decals: DecalSet { materials, decals },
        particles: 2_000,
        scene,
        look: courtyard_look,
    }
}

fn shared_stage() -> Stage {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/scenes/LightsPunctualLamp/glTF/LightsPunctualLamp.gltf");
    let scene = Scene::load(&path)
        .unwrap_or_else(|e| panic!("shared scene {} is missing or broken: {e}", path.display()));
    Stage {
        name: "LightsPunctualLamp",
        lights: scene.lights.clone(),
        decals: DecalSet::default(),
        particles: 0,
        scene,
        look: |c| c,
    }
}

/// What a sweep did: frames rendered plain and scalarized, and scalarized configurations the
/// device refused with `RenderError::Config(ConfigError::NoSubgroup)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct Counts {
    plain: usize,
    scalarized: usize,
    refused: usize,
}

fn sweep(gpu: &GpuContext, stage: &Stage) -> Counts {
    let camera = default_camera(&stage.scene, WIDTH as f32 / HEIGHT as f32);
    let subgroup = gpu.capabilities().subgroup.is_some();
    let particles =
        (stage.particles > 0).then(|| builtin_system(stage.scene.bounds, stage.particles, 1));
    let mut counts = Counts::default();
    for path in RenderPath::ALL {
        for msaa in [1, 4] {
            let mut plain = None;
            for scalarize in [false, true] {
                let config = (stage.look)(RendererConfig {
                    width: WIDTH,
                    height: HEIGHT,
                    msaa,
                    path,
                    scalarize,
                    ..Default::default()
                });
                let what = format!(
                    "{} {} MSAA {msaa} scalarize {scalarize}",
                    stage.name,
                    path.name()
                );
                if scalarize && subgroup && !path.is_culled() {
                    // The naive paths have no list to scalarize: the same shaders as plain.
                    continue;
                }
                let made = Renderer::new(gpu, config);
                if scalarize && !subgroup {
                    match made {
                        Err(RenderError::Config(ConfigError::NoSubgroup)) => counts.refused += 1,
                        Err(e) => panic!("{what}: refused with {e}, not NoSubgroup"),
                        Ok(_) => panic!("{what}: made a scalarized renderer without subgroups"),
                    }
                    continue;
                }
                let mut renderer = made.unwrap_or_else(|e| panic!("{what}: {e}"));
                renderer
                    .prepare_scene(&stage.scene)
                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                renderer
                    .set_lights(&stage.lights)
                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                renderer
                    .set_decals(&stage.decals)
                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                if let Some(p) = &particles {
                    renderer
                        .set_particles(p, WARMUP_STEPS)
                        .unwrap_or_else(|e| panic!("{what}: {e}"));
                }
                let frame = render_one_frame(gpu, &mut renderer, &camera);
                // A frame that draws nothing would pass validation trivially.
                let lit = frame
                    .rgba
                    .chunks_exact(4)
                    .filter(|p| p[..3].iter().any(|&c| c > 8))
                    .count();
                assert!(
                    lit > (WIDTH * HEIGHT / 50) as usize,
                    "{what}: only {lit} lit pixels"
                );
                if scalarize {
                    counts.scalarized += 1;
                    let plain: &Vec<u8> = plain.as_ref().expect("the plain frame comes first");
                    let worst = largest_difference(plain, &frame.rgba);
                    // Equal (measured: largest channel difference 0).
                    assert_eq!(worst, 0, "{what}: differs from the plain frame");
                } else {
                    counts.plain += 1;
                    plain = Some(frame.rgba);
                }
            }
        }
    }
    eprintln!("{}: {counts:?}", stage.name);
    counts
}

/// Asserts a sweep's counts: every path at MSAA 1 and 4 rendered plain, and scalarized where
/// the device has subgroups (the culled paths: the naive ones have no list to scalarize),
/// refused with `NoSubgroup` where it has none.
fn assert_counts(gpu: &GpuContext, counts: Counts) {
    let all = RenderPath::ALL.len() * 2;
    let culled = RenderPath::ALL.iter().filter(|p| p.is_culled()).count() * 2;
    let expected = if gpu.capabilities().subgroup.is_some() {
        Counts {
            plain: all,
            scalarized: culled,
            refused: 0,
        }
    } else {
        Counts {
            plain: all,
            scalarized: 0,
            refused: all,
        }
    };
    assert_eq!(
        counts,
        expected,
        "subgroup {:?}",
        gpu.capabilities().subgroup
    );
}

#[test]
fn every_path_msaa_and_scalarization_is_clean_under_validation_on_the_demo_scene() {
    let stage = demo_stage();
    gpu_test(|gpu| {
        let counts = sweep(gpu, &stage);
        assert_counts(gpu, counts);
    });
}

#[test]
fn every_path_msaa_and_scalarization_is_clean_under_validation_on_a_shared_scene() {
    let stage = shared_stage();
    gpu_test(|gpu| {
        let counts = sweep(gpu, &stage);
        assert_counts(gpu, counts);
    });
}

/// The same adapter opened without `SUBGROUP`: every scalarized configuration is refused with
/// the typed error, and every plain one still renders clean and lit.
#[test]
fn without_subgroups_scalarized_configurations_are_refused_with_a_typed_error() {
    let stage = shared_stage();
    gpu_test(|gpu| {
        let (features, limits) =
            renderer::gpu::requirements::for_adapter(gpu.adapter()).expect("requirements");
        let (device, queue) =
            pollster::block_on(gpu.adapter().request_device(&wgpu::DeviceDescriptor {
                label: Some("device without subgroups"),
                required_features: features - wgpu::Features::SUBGROUP,
                required_limits: limits,
                ..Default::default()
            }))
            .expect("a device without subgroups");
        let errors = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
        let sink = std::sync::Arc::clone(&errors);
        device.on_uncaptured_error(std::sync::Arc::new(move |e| {
            sink.lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .push(e.to_string());
        }));
        let bare =
            GpuContext::from_parts(gpu.instance().clone(), gpu.adapter().clone(), device, queue)
                .expect("the device has the renderer's limits");
        assert_eq!(bare.capabilities().subgroup, None);
        let counts = sweep(&bare, &stage);
        assert_counts(&bare, counts);
        bare.wait_idle().expect("idle");
        let errors = errors
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .clone();
        assert!(errors.is_empty(), "uncaptured errors: {errors:?}");
    });
}
