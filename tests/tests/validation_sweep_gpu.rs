//! Every render path under the Khronos validation layer, full frames: each path at MSAA 1 and
//! 4, plain and scalarized (where the device has subgroups), on the demo scene (the courtyard
//! with its procedural decals, shadowed lights and particles, as `cargo xtask demo` draws it)
//! and on a shared glTF scene (LightsPunctualLamp, with its own lights). The harness
//! (`tests::gpu`) fails a test on any layer error or warning; this sweep is what makes that
//! hold for every combination rather than for the ones other tests happen to draw.

use renderer::decals::{DecalSet, placement, procedural};
use renderer::frame::setup::{
    courtyard_look, default_camera, light_space, pick_shadowed, procedural_lights,
};
use renderer::frame::{RenderPath, RendererConfig};
use renderer::particles::{WARMUP_STEPS, builtin_system};
use renderer::scene::{Scene, SceneLight};
use renderer::{GpuContext, frame::Renderer};
use tests::frames::render_one_frame;
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
    let decals = placement::scatter(&scene, 32, materials.len(), 1);
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

fn sweep(gpu: &GpuContext, stage: &Stage) -> usize {
    let camera = default_camera(&stage.scene, WIDTH as f32 / HEIGHT as f32);
    let subgroup = gpu.capabilities().subgroup.is_some();
    let particles =
        (stage.particles > 0).then(|| builtin_system(stage.scene.bounds, stage.particles, 1));
    let mut frames = 0;
    for path in RenderPath::ALL {
        for msaa in [1, 4] {
            for scalarize in [false, true] {
                if scalarize && !subgroup {
                    continue;
                }
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
                let mut renderer =
                    Renderer::new(gpu, config).unwrap_or_else(|e| panic!("{what}: {e}"));
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
                frames += 1;
            }
        }
    }
    frames
}

#[test]
fn every_path_msaa_and_scalarization_is_clean_under_validation_on_the_demo_scene() {
    let stage = demo_stage();
    gpu_test(|gpu| {
        let frames = sweep(gpu, &stage);
        assert!(frames >= RenderPath::ALL.len() * 2);
    });
}

#[test]
fn every_path_msaa_and_scalarization_is_clean_under_validation_on_a_shared_scene() {
    let stage = shared_stage();
    gpu_test(|gpu| {
        let frames = sweep(gpu, &stage);
        assert!(frames >= RenderPath::ALL.len() * 2);
    });
}
