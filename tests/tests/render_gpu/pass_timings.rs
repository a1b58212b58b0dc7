//! Every graph pass is timed on a device that can time only whole compute and render passes, as
//! WebGPU can (timestamp queries without `TIMESTAMP_QUERY_INSIDE_ENCODERS`): the pass encoder
//! gives each compute and render pass its own timestamps, and the frame timings sum them per
//! graph pass. The reference is the same frame on lavapipe's full device, where the graph
//! brackets each pass with timestamps between commands.

use std::collections::BTreeSet;
use std::sync::{Arc, Mutex, PoisonError};

use renderer::GpuContext;
use renderer::frame::{RenderPath, Renderer, create_target};
use tests::gpu::gpu_test;
use web_demo::showcase::{Settings, Showcase};

/// The courtyard with every kind of pass: shadows, decals, particles.
const SETTINGS: Settings = Settings {
    path: RenderPath::Naive,
    msaa: 4,
    width: 128,
    height: 72,
    lights: 32,
    shadowed: 2,
    decals: 8,
    particles: 500,
    seed: 3,
};

/// Graph passes that record only copies and clears, which only a device that times between
/// commands can time: the depth copy the particles sample to fade at surfaces, and the compute
/// tonemap's copy into the target.
pub(crate) const COPY_ONLY: &[&str] = &["particle fade depth", "tonemap copy"];

/// A second device on `gpu`'s adapter with its features less the timestamps between commands.
fn device_timing_whole_passes_only(gpu: &GpuContext) -> GpuContext {
    let features = gpu.device().features()
        - wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS
        - wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES;
    assert!(
        features.contains(wgpu::Features::TIMESTAMP_QUERY),
        "lavapipe has timestamp queries"
    );
    let (device, queue) =
        pollster::block_on(gpu.adapter().request_device(&wgpu::DeviceDescriptor {
            label: Some("whole-pass timestamps only"),
            required_features: features,
            required_limits: gpu.device().limits(),
            ..Default::default()
        }))
        .expect("a second device");
    GpuContext::from_parts(gpu.instance().clone(), gpu.adapter().clone(), device, queue)
        .expect("the renderer accepts it")
}

/// The renderer of `showcase` at `settings` on `gpu` after one frame of its orbit camera, and
/// the target it drew.
pub(crate) fn render_showcase_frame(
    gpu: &GpuContext,
    showcase: &Showcase,
    settings: &Settings,
) -> (Renderer, wgpu::Texture) {
    let mut renderer = showcase.renderer(gpu, settings).expect("renderer");
    let target = create_target(gpu.device(), renderer.config());
    let aspect = settings.width as f32 / settings.height as f32;
    renderer
        .render(&showcase.orbit.camera(aspect), &target)
        .expect("frame");
    (renderer, target)
}

/// The names of the timed passes of one frame of `settings` on `gpu`, each with a time.
fn timed_passes(gpu: &GpuContext, settings: &Settings) -> BTreeSet<String> {
    let (mut renderer, _target) =
        render_showcase_frame(gpu, &Showcase::courtyard(settings), settings);
    let timings = renderer.finish().expect("the frame's timings arrived");
    for t in &timings {
        assert!(
            t.gpu_ms.is_finite() && t.gpu_ms >= 0.0,
            "{}: {} ms",
            t.pass,
            t.gpu_ms
        );
    }
    timings.into_iter().map(|t| t.pass).collect()
}

#[test]
fn every_graph_pass_is_timed_on_a_device_that_times_only_whole_passes() {
    gpu_test(|gpu| {
        assert!(
            gpu.capabilities().timestamp_inside_passes,
            "the reference needs timestamps between commands"
        );
        let whole_passes = device_timing_whole_passes_only(gpu);
        assert!(!whole_passes.capabilities().timestamp_inside_passes);
        let errors = Arc::new(Mutex::new(Vec::new()));
        let sink = Arc::clone(&errors);
        whole_passes
            .device()
            .on_uncaptured_error(Arc::new(move |e| {
                sink.lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .push(e.to_string());
            }));
        for path in RenderPath::ALL {
            let settings = Settings { path, ..SETTINGS };
            let reference = timed_passes(gpu, &settings);
            let timed = timed_passes(&whole_passes, &settings);
            let untimed: Vec<&String> = reference
                .difference(&timed)
                .filter(|p| !COPY_ONLY.contains(&p.as_str()))
                .collect();
            assert!(
                untimed.is_empty(),
                "{}: passes untimed where only whole passes can be timed: {untimed:?}",
                path.name()
            );
            let unknown: Vec<&String> = timed.difference(&reference).collect();
            assert!(
                unknown.is_empty(),
                "{}: timings of passes the frame graph did not time: {unknown:?}",
                path.name()
            );
        }
        whole_passes.wait_idle().expect("idle");
        let errors = errors.lock().unwrap_or_else(PoisonError::into_inner);
        assert!(errors.is_empty(), "device errors: {errors:?}");
    });
}
