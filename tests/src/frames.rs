//! Renders one frame of a scene through `renderer::frame::Renderer` and reads it back, for the
//! image tests.

use renderer::culling::lists::CullCounters;
use renderer::frame::setup::{create_target, framing_camera};
use renderer::frame::{FrameCamera, FrameReport, Renderer, RendererConfig};
use renderer::scene::{Scene, SceneLight};
use renderer::{GpuContext, readback};

/// One rendered frame: its RGBA8 pixels, the frame report and the culling counters.
#[derive(Debug)]
pub struct Frame {
    pub rgba: Vec<u8>,
    pub report: FrameReport,
    pub culling: Option<CullCounters>,
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
    let mut renderer = Renderer::new(gpu, config).expect("renderer");
    renderer.prepare_scene(scene);
    renderer.set_lights(lights).expect("lights fit");
    let target = create_target(&gpu.device, &config);
    let report = renderer.render(camera, &target).expect("frame");
    renderer.finish();
    let culling = renderer.culling_counters();
    let rgba = readback::read_texture_rgba8(&gpu.device, &gpu.queue, &target).expect("readback");
    Frame {
        rgba,
        report,
        culling,
    }
}
