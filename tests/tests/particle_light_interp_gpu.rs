//! `particle_light::light_atlas`, the particle lighting atlas kernel (a texel finds its particle
//! from its Morton cell, rebuilds its point and rounded normal on the billboard, and sums
//! ambient and its lights, shadowed), run by the DSL's host interpreter on the inputs of a real
//! lavapipe frame, against the atlas texels that frame's kernel wrote: with every light
//! (`list` 0, the naive path) and with the clustered lists (`list` 2), at subgroup sizes 4, 8,
//! 32 and 64 under three schedules. The shadow lookups compare the host's bilinear depth
//! comparison with lavapipe's.

use codegen::interp::Schedule;
use renderer::frame::create_target;
use renderer::frame::{RenderPath, Renderer, RendererConfig};
use renderer::shadow::ShadowConfig;
use shaders_gen::forward::forward::GpuLight;
use shaders_gen::shared::shadow_atlas::NO_SHADOW;
use tests::gpu::gpu_test;
use tests::particle_light_interp::{
    LIGHT_SOURCE, LightingInputsProbe, ProbedLighting, compile, host_light_atlas, unpack_rg11b10,
};
use tests::particle_stage::{WARMUP, camera, lights, particles, stage};

/// Half the stage's frame size (the same aspect).
const WIDTH: u32 = 80;
const HEIGHT: u32 = 60;

/// One lavapipe frame of the particle stage on `path`, probed after particle lighting.
fn gpu_frame(path: RenderPath) -> ProbedLighting {
    let scene = stage();
    let mut system = particles();
    system.capacity = 64;
    let config = RendererConfig {
        width: WIDTH,
        height: HEIGHT,
        path,
        particle_atlas_side: 256,
        // A small shadow atlas: the host holds every texel as a value.
        shadows: ShadowConfig {
            atlas_size: 512,
            max_resolution: 128,
            ..ShadowConfig::default()
        },
        ..Default::default()
    };
    gpu_test(|gpu| {
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        renderer.prepare_scene(&scene).expect("the scene fits");
        renderer.set_lights(&lights(&scene)).expect("lights fit");
        renderer
            .set_particles(&system, WARMUP)
            .expect("particles fit");
        renderer
            .insert_pass_after(
                "particle lighting",
                Box::new(LightingInputsProbe::default()),
            )
            .expect("the probe joins the frame");
        let target = create_target(gpu.device(), &config);
        renderer.render(&camera(), &target).expect("frame");
        renderer.finish();
        renderer
            .pass::<LightingInputsProbe>()
            .expect("the probe runs")
            .take(gpu)
            .expect("the probe's copies")
    })
}

/// Channel fields of `Rg11b10Ufloat` bits: (value, width).
fn fields(bits: u32) -> [u32; 3] {
    [bits & 0x7ff, (bits >> 11) & 0x7ff, bits >> 22]
}

fn check(path: RenderPath, list: i64, runs: &[(u32, Schedule)]) {
    let frame = gpu_frame(path);
    let gpu: Vec<u32> = bytemuck::pod_collect_to_vec(frame.buffer("LIT").expect("LIT"));
    let lit = gpu.iter().filter(|&&t| t != 0).count();
    let brightest = gpu
        .iter()
        .map(|&t| unpack_rg11b10(t).into_iter().fold(0.0, f32::max))
        .fold(0.0, f32::max);
    assert!(lit > 500, "the atlas is lit ({lit} texels)");
    let records: Vec<GpuLight> =
        bytemuck::pod_collect_to_vec(frame.buffer("LIGHTS").expect("LIGHTS"));
    assert!(
        records.iter().any(|l| l.shadow != NO_SHADOW),
        "a light reads the shadow atlas"
    );
    let c = compile(LIGHT_SOURCE).expect("the particle lighting module compiles");
    for &(subgroup_size, schedule) in runs {
        let started = std::time::Instant::now();
        let host = host_light_atlas(&c, list, &frame, subgroup_size, schedule)
            .unwrap_or_else(|e| panic!("list {list}, subgroup {subgroup_size}, {schedule:?}: {e}"));
        // Each channel is an unsigned float: adjacent values are adjacent integers, so a
        // rounding difference of the last bit is a field difference of 1.
        let mut last_bit = 0;
        for (i, (h, g)) in host.iter().zip(&gpu).enumerate() {
            let steps = fields(*h)
                .iter()
                .zip(fields(*g))
                .map(|(a, b)| a.abs_diff(b))
                .max()
                .unwrap_or(0);
            assert!(
                steps <= 1,
                "texel {i}: host {:?}, GPU {:?} (list {list}, subgroup {subgroup_size})",
                unpack_rg11b10(*h),
                unpack_rg11b10(*g)
            );
            last_bit += usize::from(steps == 1);
        }
        eprintln!(
            "host particle lighting, list {list}, {lit} texels lit (brightest {brightest:.2}), \
             subgroup {subgroup_size}, {schedule:?}: {:.0} ms, {last_bit} texels off by the \
             last bit",
            started.elapsed().as_secs_f64() * 1e3
        );
        // Measured: a few dozen texels round the other way; more means a real difference.
        assert!(
            last_bit * 50 < lit,
            "{last_bit} of {lit} texels off by the last bit"
        );
    }
}

#[test]
fn host_particle_lighting_with_every_light_equals_the_gpu_atlas() {
    check(
        RenderPath::Naive,
        0,
        &[(4, Schedule::InOrder), (64, Schedule::Shuffled(2))],
    );
}

#[test]
fn host_particle_lighting_from_clustered_lists_equals_the_gpu_atlas() {
    check(
        RenderPath::Clustered,
        2,
        &[(8, Schedule::Reversed), (32, Schedule::InOrder)],
    );
}
