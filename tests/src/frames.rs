//! Renders one frame of a scene through `renderer::frame::Renderer` and reads it back, for the
//! image tests.

use renderer::culling::lists::CullCounters;
use renderer::decals::DecalSet;
use renderer::frame::{FrameCamera, FrameReport, Renderer, RendererConfig};
use renderer::frame::{create_target, framing_camera};
use renderer::scene::{LightKind, Scene, SceneLight};

/// The courtyard tests' warm sun: a shadowed directional light from above, at an angle.
pub fn courtyard_sun() -> SceneLight {
    SceneLight {
        kind: LightKind::Directional,
        position: glam::Vec3::ZERO,
        direction: glam::Vec3::new(-0.4, -1.0, -0.3).normalize(),
        color: glam::Vec3::new(1.0, 0.9, 0.8),
        intensity: 0.6,
        range: None,
        casts_shadow: true,
    }
}

/// The glTF scene committed with the tests (every alpha mode: opaque, masked, blended).
pub fn committed_scene() -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/AlphaBlendModeTest/AlphaBlendModeTest.glb");
    Scene::load(path).unwrap_or_else(|e| panic!("{e}"))
}

/// The largest difference of one 8-bit channel between two images.
pub fn largest_difference(a: &[u8], b: &[u8]) -> u8 {
    a.iter()
        .zip(b)
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap_or(0)
}
use renderer::{GpuContext, readback};

/// One rendered frame: its RGBA8 pixels, the frame report and the culling counters.
#[derive(Debug)]
pub struct Frame {
    pub rgba: Vec<u8>,
    pub report: FrameReport,
    pub culling: Option<CullCounters>,
    /// The frame's graph in Graphviz DOT (`Renderer::graph_dot`).
    pub graph_dot: String,
}

/// Renders `scene` lit by `lights` with `config`, from a camera framing the scene's bounds.
pub fn render_frame(
    gpu: &GpuContext,
    scene: &Scene,
    config: RendererConfig,
    lights: &[SceneLight],
) -> Frame {
    let camera = framing_camera(scene.bounds, config.width as f32 / config.height as f32);
    render_frame_from(gpu, scene, config, lights, &camera)
}

/// [`render_frame`] from `camera`.
pub fn render_frame_from(
    gpu: &GpuContext,
    scene: &Scene,
    config: RendererConfig,
    lights: &[SceneLight],
    camera: &FrameCamera,
) -> Frame {
    render_frame_with(gpu, scene, config, lights, &DecalSet::default(), camera)
}

/// [`render_frame_from`] with `decals`: one frame, the first the renderer draws (see
/// [`render_one_frame`]).
pub fn render_frame_with(
    gpu: &GpuContext,
    scene: &Scene,
    config: RendererConfig,
    lights: &[SceneLight],
    decals: &DecalSet,
    camera: &FrameCamera,
) -> Frame {
    let mut renderer = Renderer::new(gpu, config).expect("renderer");
    renderer
        .prepare_scene(scene)
        .expect("the scene fits the device");
    renderer.set_lights(lights).expect("lights fit");
    renderer.set_decals(decals).expect("decals fit");
    render_one_frame(gpu, &mut renderer, camera)
}

/// Renders `renderer`'s next frame from `camera` into a new target, waits for it and reads it
/// back with its culling counters. Never renders twice, and fails the test if the frame dropped
/// a list entry: the renderer sizes its lists before every frame, the first included.
pub fn render_one_frame(gpu: &GpuContext, renderer: &mut Renderer, camera: &FrameCamera) -> Frame {
    let target = create_target(gpu.device(), renderer.config());
    let report = renderer.render(camera, &target).expect("frame");
    renderer.finish();
    let culling = renderer.culling_counters();
    if let Some(c) = culling {
        assert_eq!(
            c.dropped, 0,
            "the frame dropped list entries ({} requested): lists must be sized before the frame",
            c.requested_entries
        );
    }
    let rgba = readback::read_texture_rgba8(gpu.device(), gpu.queue(), &target).expect("readback");
    Frame {
        rgba,
        report,
        culling,
        graph_dot: renderer.graph_dot().unwrap_or_default(),
    }
}
