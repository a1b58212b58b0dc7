//! Particle lighting against an independent CPU evaluation of its specification
//! (`docs/particle_lighting.md`, `tests::particle_light_reference`): every texel of the lit atlas
//! a lavapipe frame draws from, on the naive and the clustered path; and the frame itself, whose
//! smoke, drawn from an atlas of CPU-lit texels in the GPU frame's own layout, equals the smoke
//! drawn from the GPU's atlas at every pixel, and the smoke lit per pixel within the atlas's
//! tolerance at every smoke pixel.
//!
//! Mutations of the shaders this catches (each run, seen failing, reverted): the half-Lambert
//! wrap without its offset (`0.5 · n·l` in `pbr::particle_light`), the shadow term ignored in
//! `particle_light`'s `particle_contribution`, and the range window's `r · r` as `r`
//! (`pbr::light_incidence`).

use glam::Vec3;
use renderer::frame::create_target;
use renderer::frame::{ParticleLighting, RenderPath, Renderer, RendererConfig};
use renderer::passes::Pass;
use renderer::scene::Scene;
use renderer::shadow::ShadowConfig;
use renderer::{GpuContext, readback};
use tests::gpu::gpu_test;
use tests::particle_atlas_probe::{AtlasOverride, AtlasProbe, ProbedAtlas};
use tests::particle_light_interp::unpack_rg11b10;
use tests::particle_light_reference::pack_rg11b10;
use tests::particle_stage::{HEIGHT, WARMUP, WIDTH, camera, lights, particles, stage};

fn config(path: RenderPath, msaa: u32, lighting: ParticleLighting) -> RendererConfig {
    RendererConfig {
        width: WIDTH,
        height: HEIGHT,
        msaa,
        path,
        particle_lighting: lighting,
        particle_atlas_side: 256,
        // A smaller shadow atlas than the default: its depth is read back whole.
        shadows: ShadowConfig {
            atlas_size: 1024,
            max_resolution: 256,
            ..ShadowConfig::default()
        },
        ..Default::default()
    }
}

/// The stage's first frame after the warm-up, with `extra` inserted after particle lighting
/// (or without particles), and its RGBA8 pixels.
fn frame(
    gpu: &GpuContext,
    scene: &Scene,
    config: RendererConfig,
    extra: Option<Box<dyn Pass>>,
    with_particles: bool,
) -> (Renderer, Vec<u8>) {
    let mut renderer = Renderer::new(gpu, config).expect("renderer");
    renderer.prepare_scene(scene).expect("the scene fits");
    renderer.set_lights(&lights(scene)).expect("lights fit");
    if with_particles {
        renderer
            .set_particles(&particles(), WARMUP)
            .expect("particles fit");
    }
    if let Some(pass) = extra {
        renderer
            .insert_pass_after("particle lighting", pass)
            .expect("the pass joins the frame");
    }
    let target = create_target(gpu.device(), &config);
    renderer.render(&camera(), &target).expect("frame");
    renderer.finish();
    let rgba = readback::read_texture_rgba8(gpu.device(), gpu.queue(), &target).expect("readback");
    (renderer, rgba)
}

fn probed_frame(gpu: &GpuContext, scene: &Scene, config: RendererConfig) -> (ProbedAtlas, Vec<u8>) {
    let (renderer, rgba) = frame(
        gpu,
        scene,
        config,
        Some(Box::new(AtlasProbe::default())),
        true,
    );
    let probed = renderer
        .pass::<AtlasProbe>()
        .expect("the probe runs")
        .take(gpu)
        .expect("the probe's copies");
    (probed, rgba)
}

/// Each channel's allowed difference between a stored texel and the CPU response `c`: the
/// format's rounding (half a unit of the last mantissa bit: up to `2⁻⁷ c` red and green,
/// `2⁻⁶ c` blue), plus `2⁻⁸ c` for the GPU's bilinear comparison weights (lavapipe filters
/// with 8 bits of sub-texel position) and `f32` rounding, plus `10⁻⁴` where `c` is near 0.
/// Measured on lavapipe: at most 0.96 of `2⁻⁶ c + 10⁻⁴`, so about 0.77 of this.
fn texel_tolerance(c: f32) -> f32 {
    c * (1.0 / 64.0 + 1.0 / 256.0) + 1.0e-4
}

/// The CPU response at every texel the frame's visible particles own, against the atlas the
/// GPU drew from; also the atlas with the CPU's texels in place of the GPU's.
fn compare_atlas(probed: &ProbedAtlas, what: &str) -> Vec<u32> {
    let scene = probed.scene();
    let regions = probed.regions();
    assert!(
        regions.len() >= 50,
        "{what}: {} particles visible",
        regions.len()
    );
    let mut unshadowed = scene.clone();
    for l in &mut unshadowed.punctual {
        l.shadow = u32::MAX;
    }
    let mut cpu_atlas = probed.atlas.clone();
    let (mut texels, mut shadowed, mut worst) = (0, 0, 0.0f32);
    let mut failures = vec![];
    for region in regions {
        let plain = unshadowed.light_region(region);
        for ((texel, cpu), (_, open)) in scene.light_region(region).into_iter().zip(plain) {
            let at = (texel.y * probed.side + texel.x) as usize;
            let gpu = Vec3::from(unpack_rg11b10(probed.atlas[at]));
            cpu_atlas[at] = pack_rg11b10(cpu);
            texels += 1;
            // Texels a shadow darkens by over a tenth: the shadow term is exercised.
            shadowed += usize::from(open.max_element() > cpu.max_element() * 1.1);
            let excess = (0..3)
                .map(|ch| (gpu[ch] - cpu[ch]).abs() / texel_tolerance(cpu[ch]))
                .fold(0.0, f32::max);
            worst = worst.max(excess);
            if excess > 1.0 && failures.len() < 8 {
                failures.push(format!("texel {texel}: GPU {gpu}, CPU {cpu}"));
            }
        }
    }
    eprintln!(
        "{what}: {texels} texels, {shadowed} in shadow; largest difference {worst:.3} of the \
         tolerance"
    );
    assert!(
        failures.is_empty(),
        "{what}: the atlas differs from the CPU evaluation:\n{}",
        failures.join("\n")
    );
    assert!(texels > 1000, "{what}: only {texels} texels lit");
    assert!(shadowed > 20, "{what}: only {shadowed} texels in shadow");
    cpu_atlas
}

#[test]
fn every_atlas_texel_equals_the_cpu_evaluation() {
    gpu_test(|gpu| {
        let scene = stage();
        for path in [RenderPath::Naive, RenderPath::Clustered] {
            let (probed, _) = probed_frame(gpu, &scene, config(path, 1, ParticleLighting::Atlas));
            compare_atlas(&probed, path.name());
        }
    });
}

/// Per pixel and channel of two RGBA8 images, the absolute differences.
fn differences(a: &[u8], b: &[u8]) -> Vec<[u8; 3]> {
    a.chunks(4)
        .zip(b.chunks(4))
        .map(|(p, q)| [0, 1, 2].map(|c| p[c].abs_diff(q[c])))
        .collect()
}

/// Largest difference among the pixels `select` picks, and where.
fn largest(d: &[[u8; 3]], select: impl Fn(usize) -> bool) -> (u8, usize) {
    d.iter()
        .enumerate()
        .filter(|(i, _)| select(*i))
        .map(|(i, p)| (p.iter().copied().max().unwrap_or(0), i))
        .max()
        .unwrap_or((0, 0))
}

/// Smoke lit from the CPU's texels, against smoke lit from the GPU's, in 8-bit steps after
/// tonemapping at any smoke pixel: texels within [`texel_tolerance`] move a pixel by at most a
/// step. Measured on lavapipe: largest 0.
const CPU_ATLAS_LARGEST: u8 = 1;
/// Smoke lit from the CPU's texels against smoke lit per pixel, at any smoke pixel: the atlas's
/// own resolution limit (a 2–32-texel region under a B-spline against exact lighting at each
/// pixel; see `particle_render_gpu.rs`). Measured on lavapipe: largest 5.
const PER_PIXEL_LARGEST: u8 = 8;

#[test]
fn smoke_lit_from_the_cpu_atlas_matches_the_gpu_frame_at_every_smoke_pixel() {
    gpu_test(|gpu| {
        let scene = stage();
        for (path, msaa) in [(RenderPath::NaivePrez, 1), (RenderPath::Clustered, 4)] {
            let what = format!("{} at MSAA {msaa}", path.name());
            let atlas = config(path, msaa, ParticleLighting::Atlas);
            let (probed, gpu_lit) = probed_frame(gpu, &scene, atlas);
            let cpu_texels = compare_atlas(&probed, &what);
            let pass = AtlasOverride::new(&probed, cpu_texels);
            let (_, cpu_lit) = frame(gpu, &scene, atlas, Some(Box::new(pass)), true);
            let (_, bare) = frame(gpu, &scene, atlas, None, false);
            let per_pixel = config(path, msaa, ParticleLighting::PerPixel);
            let (_, pixel_lit) = frame(gpu, &scene, per_pixel, None, true);
            // Smoke pixels: where either atlas frame differs from the frame without particles.
            let smoke: Vec<bool> = differences(&gpu_lit, &bare)
                .iter()
                .zip(differences(&cpu_lit, &bare))
                .map(|(a, b)| a.iter().chain(&b).any(|&d| d > 0))
                .collect();
            let count = smoke.iter().filter(|&&s| s).count();
            assert!(count > 800, "{what}: only {count} smoke pixels");
            let to_gpu = differences(&cpu_lit, &gpu_lit);
            let to_pixel = differences(&cpu_lit, &pixel_lit);
            let (off_smoke, at) = largest(&to_gpu, |i| !smoke[i]);
            let (gpu_worst, gpu_at) = largest(&to_gpu, |i| smoke[i]);
            let (pixel_worst, pixel_at) = largest(&to_pixel, |i| smoke[i]);
            let xy = |i: usize| (i % WIDTH as usize, i / WIDTH as usize);
            eprintln!(
                "{what}: {count} smoke pixels; CPU-lit against GPU-lit largest {gpu_worst} at \
                 {:?}, against per-pixel largest {pixel_worst} at {:?}",
                xy(gpu_at),
                xy(pixel_at)
            );
            assert_eq!(
                off_smoke,
                0,
                "{what}: pixel {:?} off the smoke differs",
                xy(at)
            );
            assert!(
                gpu_worst <= CPU_ATLAS_LARGEST,
                "{what}: smoke from the CPU's texels differs from the GPU's by {gpu_worst} at \
                 {:?} (at most {CPU_ATLAS_LARGEST})",
                xy(gpu_at)
            );
            assert!(
                pixel_worst <= PER_PIXEL_LARGEST,
                "{what}: smoke from the CPU's texels differs from per-pixel lighting by \
                 {pixel_worst} at {:?} (at most {PER_PIXEL_LARGEST})",
                xy(pixel_at)
            );
        }
    });
}
