//! Particles end to end through the renderer: smoke lit once per frame into the lighting atlas
//! and drawn from it looks like the same smoke lit per pixel, on every path and at MSAA 1 and 4;
//! a wrong atlas mapping (each particle sampling another's region) is caught.

use renderer::frame::setup::create_target;
use renderer::frame::{
    FrameReport, ParticleLighting, RenderError, RenderPath, Renderer, RendererConfig,
};
use renderer::frame_data::{FrameInputs, FrameResources};
use renderer::graph::{BufferAccess, RenderGraph};
use renderer::passes::Pass;
use renderer::scene::Scene;
use renderer::{GpuContext, readback};
use tests::gpu::gpu_test;
use tests::particle_stage::{HEIGHT, WARMUP, WIDTH, camera, lights, particles, stage};

/// A renderer with the stage, its lights and the smoke, for `config`.
fn renderer(gpu: &GpuContext, scene: &Scene, config: RendererConfig) -> Renderer {
    let mut renderer = Renderer::new(gpu, config).expect("renderer");
    renderer
        .prepare_scene(scene)
        .expect("the scene fits the device");
    renderer.set_lights(&lights(scene)).expect("lights fit");
    renderer
        .set_particles(&particles(), WARMUP)
        .expect("particles fit");
    renderer
}

/// One frame (the first after the warm-up) and its report.
fn render(
    renderer: &mut Renderer,
    config: &RendererConfig,
    gpu: &GpuContext,
) -> (Vec<u8>, FrameReport) {
    let target = create_target(&gpu.device, config);
    let report = renderer.render(&camera(), &target).expect("frame");
    renderer.finish();
    let rgba = readback::read_texture_rgba8(&gpu.device, &gpu.queue, &target).expect("readback");
    (rgba, report)
}

fn config(path: RenderPath, msaa: u32, lighting: ParticleLighting) -> RendererConfig {
    RendererConfig {
        width: WIDTH,
        height: HEIGHT,
        msaa,
        path,
        particle_lighting: lighting,
        particle_atlas_side: 256,
        ..Default::default()
    }
}

/// Per-channel differences of two RGBA8 images: (mean, 99th percentile, largest).
fn difference_stats(a: &[u8], b: &[u8]) -> (f64, u8, u8) {
    let mut d: Vec<u8> = a
        .chunks(4)
        .zip(b.chunks(4))
        .flat_map(|(p, q)| (0..3).map(move |c| p[c].abs_diff(q[c])))
        .collect();
    let mean = d.iter().map(|&x| f64::from(x)).sum::<f64>() / d.len() as f64;
    d.sort_unstable();
    (mean, d[d.len() * 99 / 100], d[d.len() - 1])
}

/// The tolerance of atlas against per-pixel lighting, in 8-bit steps after tonemapping: the
/// mean over all channels and the 99th percentile. Lighting is low-frequency over a particle
/// (smooth falloff, half-Lambert wrap, no specular), so a region of 2–32 texels sampled with a
/// B-spline holds it to within a few steps; what differs is the curvature of the falloff of a
/// light very near a puff and shadow edges across it, which the atlas resolves at texel size.
/// Measured on lavapipe: mean 0.08, 99th percentile 2, largest 7.
const MEAN_TOLERANCE: f64 = 0.5;
const P99_TOLERANCE: u8 = 4;

#[test]
fn atlas_lit_smoke_matches_per_pixel_lit_smoke() {
    gpu_test(|gpu| {
        let scene = stage();
        for path in [
            RenderPath::NaivePrez,
            RenderPath::Tiled,
            RenderPath::Clustered,
        ] {
            for msaa in [1, 4] {
                let atlas = config(path, msaa, ParticleLighting::Atlas);
                let pixel = config(path, msaa, ParticleLighting::PerPixel);
                let (a, _) = render(&mut renderer(gpu, &scene, atlas), &atlas, gpu);
                let (p, _) = render(&mut renderer(gpu, &scene, pixel), &pixel, gpu);
                let without = config(path, msaa, ParticleLighting::Atlas);
                let mut bare = renderer(gpu, &scene, without);
                bare.clear_particles();
                let (empty, _) = render(&mut bare, &without, gpu);
                let (mean, p99, largest) = difference_stats(&a, &p);
                let what = format!("{} at MSAA {msaa}", path.name());
                eprintln!("{what}: mean {mean:.3}, 99th percentile {p99}, largest {largest}");
                // The smoke is there: many pixels differ from the frame without it.
                let smoke_pixels = changed_pixels(&a, &empty, 8);
                assert!(
                    smoke_pixels > 800,
                    "{what}: only {smoke_pixels} pixels show smoke"
                );
                assert!(
                    mean <= MEAN_TOLERANCE && p99 <= P99_TOLERANCE,
                    "{what}: atlas and per-pixel lighting differ by mean {mean:.3}, 99th \
                     percentile {p99} (tolerances {MEAN_TOLERANCE}, {P99_TOLERANCE})"
                );
            }
        }
    });
}

/// Pixels whose colour differs by more than `by` in some channel.
fn changed_pixels(a: &[u8], b: &[u8], by: u8) -> usize {
    a.chunks(4)
        .zip(b.chunks(4))
        .filter(|(p, q)| p.iter().zip(*q).any(|(x, y)| x.abs_diff(*y) > by))
        .count()
}

/// An engine's pass that breaks the atlas mapping: after the atlas is lit, every particle's
/// region is replaced by the next slot's, so each samples another particle's lighting.
#[derive(Debug)]
struct ShiftRegions;

impl Pass for ShiftRegions {
    fn name(&self) -> &'static str {
        "shift particle regions"
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        _frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let Some(p) = resources.particles.as_mut() else {
            return Ok(());
        };
        let regions = p.regions.clone();
        graph
            .add_pass(self.name())
            .write_buffer(&mut p.laid_out, BufferAccess::StorageWrite)
            .execute(move |ctx| {
                let size = regions.size();
                let scratch = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("shifted regions"),
                    size,
                    usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                });
                ctx.encoder
                    .copy_buffer_to_buffer(&regions, 4, &scratch, 0, size - 4);
                ctx.encoder
                    .copy_buffer_to_buffer(&regions, 0, &scratch, size - 4, 4);
                ctx.encoder
                    .copy_buffer_to_buffer(&scratch, 0, &regions, 0, size);
            });
        Ok(())
    }
}

#[test]
fn a_wrong_atlas_mapping_fails_the_comparison() {
    gpu_test(|gpu| {
        let scene = stage();
        let atlas = config(RenderPath::Clustered, 4, ParticleLighting::Atlas);
        let pixel = config(RenderPath::Clustered, 4, ParticleLighting::PerPixel);
        let mut wrong = renderer(gpu, &scene, atlas);
        wrong
            .insert_pass_after("particle lighting", Box::new(ShiftRegions))
            .expect("the lighting pass is in the list");
        let (a, _) = render(&mut wrong, &atlas, gpu);
        let (p, _) = render(&mut renderer(gpu, &scene, pixel), &pixel, gpu);
        let (mean, p99, largest) = difference_stats(&a, &p);
        eprintln!("shifted regions: mean {mean:.3}, 99th percentile {p99}, largest {largest}");
        assert!(
            mean > MEAN_TOLERANCE || p99 > P99_TOLERANCE,
            "a wrong atlas mapping passed: mean {mean:.3}, 99th percentile {p99}"
        );
    });
}

#[test]
fn the_report_counts_particles_and_a_full_atlas_shrinks() {
    gpu_test(|gpu| {
        let scene = stage();
        let mut config = config(RenderPath::Clustered, 1, ParticleLighting::Atlas);
        // The smallest atlas the pool allows: 64² texels, while near particles want 8–16².
        config.particle_atlas_side = 64;
        let mut renderer = renderer(gpu, &scene, config);
        let target = create_target(&gpu.device, &config);
        let mut last = None;
        for _ in 0..6 {
            let report = renderer.render(&camera(), &target).expect("frame");
            renderer.finish();
            last = report.particles.or(last);
        }
        let report = last.expect("particle counters arrive within six frames");
        assert!(report.alive > 100 && report.visible > 100, "{report:?}");
        assert!(
            report.atlas_shrink > 0 && report.shrunk_frames > 0,
            "{report:?}"
        );
        assert!(report.atlas_cells <= 32 * 32, "{report:?}");
        assert_eq!(report.starved, 0, "{report:?}");
    });
}

#[test]
fn bad_particle_inputs_are_clear_errors() {
    gpu_test(|gpu| {
        let scene = stage();
        let mut config = config(RenderPath::Clustered, 1, ParticleLighting::Atlas);
        config.particle_atlas_side = 100;
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        renderer
            .prepare_scene(&scene)
            .expect("the scene fits the device");
        let mut bad = particles();
        bad.capacity = 0;
        let err = renderer.set_particles(&bad, 0).unwrap_err().to_string();
        assert!(err.contains("capacity is 0"), "{err}");
        renderer.set_particles(&particles(), 0).expect("particles");
        let target = create_target(&gpu.device, &config);
        let err = renderer.render(&camera(), &target).unwrap_err().to_string();
        assert!(err.contains("power of two"), "{err}");
    });
}
