//! The TBDR tests' stages (the courtyard and the committed glTF scene, with their lights and
//! cameras) and one frame of a stage on a render path, with what the TBDR pass recorded.

use renderer::demo::{courtyard_look, procedural_lights};
use renderer::frame::{FrameCamera, RenderPath, Renderer, RendererConfig};
use renderer::frame::{create_target, default_camera};
use renderer::frame_data::EdgeThresholds;
use renderer::passes::deferred::{TbdrPass, TbdrRecord};
use renderer::scene::{Scene, SceneLight};
use renderer::{GpuContext, readback};

use crate::frames::committed_scene;

/// A scene, its lights and camera, and the frame size.
#[derive(Debug)]
pub struct Stage {
    pub scene: Scene,
    pub lights: Vec<SceneLight>,
    pub camera: FrameCamera,
    pub size: (u32, u32),
    pub look: fn(RendererConfig) -> RendererConfig,
}

/// The courtyard from its own camera, with its lights and 256 seeded ones.
pub fn courtyard_stage() -> Stage {
    use renderer::scene::procedural::{COURTYARD_LIGHT_REGION, courtyard};
    let scene = courtyard();
    let mut lights = scene.lights.clone();
    lights.extend(procedural_lights(COURTYARD_LIGHT_REGION, 256, 7, 0.8, 2.6));
    let (w, h) = (192, 108);
    Stage {
        camera: default_camera(&scene, w as f32 / h as f32),
        scene,
        lights,
        size: (w, h),
        look: courtyard_look,
    }
}

/// The committed glTF scene (opaque, masked and blended quads) with 64 seeded lights.
pub fn gltf_stage() -> Stage {
    let scene = committed_scene();
    let size = (scene.bounds.max - scene.bounds.min).length();
    let lights = procedural_lights(scene.bounds, 64, 3, size * 0.05, size * 0.3);
    let (w, h) = (128, 96);
    Stage {
        camera: renderer::frame::framing_camera(scene.bounds, w as f32 / h as f32),
        scene,
        lights,
        size: (w, h),
        look: |c| c,
    }
}

/// A generated city of 1,500 instances (towers, domes, columns, masked screens, glass) from its
/// street camera, with 256 seeded lights along the streets around it.
pub fn city_stage() -> Stage {
    let city = renderer::scene::procedural::builtin("city:1500")
        .expect("a valid name")
        .expect("a built-in scene");
    let (min, max) = city.light_radii;
    let lights = procedural_lights(city.light_region, 256, 5, min, max);
    let (w, h) = (192, 108);
    Stage {
        camera: default_camera(&city.scene, w as f32 / h as f32),
        scene: city.scene,
        lights,
        size: (w, h),
        look: |c| c,
    }
}

/// One frame of `stage` on `path`, its pixels, and with `record` what TBDR recorded.
pub fn frame(
    gpu: &GpuContext,
    stage: &Stage,
    path: RenderPath,
    msaa: u32,
    edges: EdgeThresholds,
    record: bool,
) -> (Vec<u8>, Option<TbdrRecord>) {
    let config = RendererConfig {
        width: stage.size.0,
        height: stage.size.1,
        msaa,
        path,
        tile: 16,
        edges,
        ..Default::default()
    };
    frame_with(gpu, stage, config, record)
}

/// [`frame`] with every setting of `config` (the stage's `look` applied over it).
pub fn frame_with(
    gpu: &GpuContext,
    stage: &Stage,
    config: RendererConfig,
    record: bool,
) -> (Vec<u8>, Option<TbdrRecord>) {
    let config = (stage.look)(config);
    let mut renderer = Renderer::new(gpu, config).expect("renderer");
    renderer
        .prepare_scene(&stage.scene)
        .expect("the scene fits the device");
    renderer.set_lights(&stage.lights).expect("lights fit");
    if record {
        renderer
            .pass_mut::<TbdrPass>()
            .expect("a TBDR path runs the TBDR pass")
            .set_recording(true);
    }
    let target = create_target(gpu.device(), &config);
    // One frame: lists are sized before every frame, the first included.
    renderer.render(&stage.camera, &target).expect("frame");
    renderer.finish();
    if config.reads_compute_samples() {
        // Every pass of the compute rasteriser's frame reads its samples: none reads a depth
        // target, so the graph leaves the depth resolve out.
        let passes = renderer.graph_passes().expect("the frame's graph");
        assert!(
            !passes.iter().any(|p| p == "visibility depth"),
            "the compute rasteriser's frame resolved a depth target: {passes:?}"
        );
    }
    if let Some(c) = renderer.culling_counters() {
        assert_eq!(c.dropped, 0, "the frame dropped list entries");
    }
    let rgba = readback::read_texture_rgba8(gpu.device(), gpu.queue(), &target).expect("readback");
    let recorded = renderer
        .pass::<TbdrPass>()
        .map(|p| p.recorded().expect("record readback"))
        .and_then(|r| r);
    (rgba, recorded)
}
