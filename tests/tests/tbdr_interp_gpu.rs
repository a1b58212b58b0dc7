//! `tbdr::shade`, the TBDR kernel (tile depth bounds, edge detection, light culling in
//! workgroup memory, PBR shading with shadow-atlas lookups, per-sample shading of edge pixels),
//! run by the DSL's host interpreter on the inputs of a real lavapipe frame, against that
//! frame's own image: at subgroup sizes 4, 8, 32 and 64 under three schedules, scalarized and
//! plain, MSAA 1 and 4, edge pixels shaded inline and deferred. The shadow lookups compare the
//! host's bilinear depth comparison with lavapipe's.
//!
//! The same frame's G-buffer also checks `tbdr::capture_gbuffer` (which recorded it) and
//! `depth_probe::probe` (the frame capture's depth probes) on the host.
//!
//! The mutation: an off-by-one in the scalarized light append (`subgroup_inclusive_add` for
//! `subgroup_exclusive_add`) leaves a list slot unwritten and writes one past the list; the
//! image comes out wrong, and the interpreter's unwritten-read check names the line that reads
//! the hole.

use codegen::interp::{EvalError, Schedule};
use renderer::demo::{courtyard_look, light_space};
use renderer::demo::{pick_shadowed, procedural_lights};
use renderer::frame::FrameCamera;
use renderer::frame::capture::FrameCapture;
use renderer::frame::{RenderPath, Renderer, RendererConfig};
use renderer::frame::{create_target, default_camera};
use renderer::passes::deferred::TbdrPass;
use renderer::scene::{Scene, SceneLight};
use renderer::shadow::ShadowConfig;
use shaders_gen::forward::forward::GpuLight;
use shaders_gen::inspect::depth_probe::ProbeParams;
use shaders_gen::shared::shadow_atlas::NO_SHADOW;
use tests::gpu::gpu_test;
use tests::tbdr_interp::{
    HostRun, KernelInputsProbe, ProbedFrame, TBDR_SOURCE, compile, host_capture, host_shade,
};

#[path = "tbdr_interp_gpu/visibility.rs"]
mod visibility;

const WIDTH: u32 = 64;
const HEIGHT: u32 = 48;
const TILE: u32 = 8;

/// The courtyard as the host-replay tests render it on `path`: 40 point lights (4 of them
/// shadowed) and a shadowed sun, a small shadow atlas, at [`WIDTH`]×[`HEIGHT`].
fn courtyard_frame(
    path: RenderPath,
    msaa: u32,
    scalarize: bool,
) -> (Scene, Vec<SceneLight>, FrameCamera, RendererConfig) {
    let scene = renderer::scene::procedural::courtyard();
    let (region, (rmin, rmax)) = light_space(&scene, true);
    let mut lights = procedural_lights(region, 40, 5, rmin, rmax);
    let camera = default_camera(&scene, WIDTH as f32 / HEIGHT as f32);
    pick_shadowed(&mut lights, &camera, HEIGHT as f32, 4);
    lights.push(tests::frames::courtyard_sun());
    let config = courtyard_look(RendererConfig {
        width: WIDTH,
        height: HEIGHT,
        msaa,
        path,
        tile: TILE,
        scalarize,
        shadows: ShadowConfig {
            atlas_size: 512,
            max_resolution: 128,
            cascade_resolution: 128,
            ..ShadowConfig::default()
        },
        ..Default::default()
    });
    (scene, lights, camera, config)
}

/// One lavapipe frame of the courtyard on a TBDR path ([`courtyard_frame`]), probed, and its
/// depth probes every [`PROBE_STRIDE`] pixels.
fn gpu_frame(path: RenderPath, msaa: u32, scalarize: bool) -> (ProbedFrame, FrameCapture) {
    let (scene, lights, camera, config) = courtyard_frame(path, msaa, scalarize);
    gpu_test(|gpu| {
        let info = gpu.adapter().get_info();
        eprintln!(
            "GPU frame on {} (subgroups of {} to {})",
            info.name, info.subgroup_min_size, info.subgroup_max_size
        );
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        renderer.prepare_scene(&scene).expect("the scene fits");
        renderer.set_lights(&lights).expect("lights fit");
        renderer
            .pass_mut::<TbdrPass>()
            .expect("a TBDR path runs the TBDR pass")
            .set_recording(true);
        renderer
            .insert_pass_after("tbdr shading", Box::new(KernelInputsProbe::default()))
            .expect("the probe joins the frame");
        renderer
            .capture_next_frame(PROBE_STRIDE)
            .expect("the TBDR path has depth");
        let target = create_target(gpu.device(), &config);
        renderer.render(&camera, &target).expect("frame");
        renderer.finish();
        let capture = renderer
            .take_capture()
            .expect("capture readback")
            .expect("the frame captured");
        let record = renderer
            .pass::<TbdrPass>()
            .and_then(|p| p.recorded().expect("record readback"))
            .expect("the frame recorded");
        let probed = renderer
            .pass::<KernelInputsProbe>()
            .expect("the probe runs")
            .take(gpu, record)
            .expect("the probe's copies");
        (probed, capture)
    })
}

/// Pixels between depth probes: odd, so the last column and row clamp to the frame's edge.
const PROBE_STRIDE: u32 = 7;

/// How far the host's image is from the GPU's: the largest difference of a channel relative to
/// `1 +` its size, and how many pixels are off by more than `tolerance`.
fn difference(frame: &ProbedFrame, host: &[[f32; 4]], tolerance: f32) -> (f32, usize) {
    pixel_difference(&frame.hdr, host, tolerance)
}

/// How far `host` is from `gpu` (RGBA rows): the largest difference of a channel relative to
/// `1 +` its size, and how many pixels are off by more than `tolerance`.
fn pixel_difference(gpu: &[[f32; 4]], host: &[[f32; 4]], tolerance: f32) -> (f32, usize) {
    let mut largest = 0.0f32;
    let mut off = 0;
    for (g, h) in gpu.iter().zip(host) {
        let d = (0..3)
            .map(|c| (g[c] - h[c]).abs() / (1.0 + g[c].abs()))
            .fold(0.0, f32::max);
        largest = largest.max(if d.is_nan() { f32::INFINITY } else { d });
        off += usize::from(d.is_nan() || d > tolerance);
    }
    (largest, off)
}

/// Host against GPU, relative to `1 +` the value: the GPU stores half floats (2⁻¹¹ relative),
/// and lavapipe's `exp2`, `pow` and filtering weights are not the host's. Measured: 0.011% at
/// most, over every variant, subgroup size and schedule (`vis_shade`: 0.012%). The off-by-one
/// mutation measures 0.8%: the light it drops and the one it shades twice are dim at most
/// pixels they reach.
const TOLERANCE: f32 = 0.002;

fn check(axes: &[(&str, i64)], path: RenderPath, msaa: u32, runs: &[(u32, Schedule)]) {
    let scalarize = axes.contains(&("scalarize", 1));
    let (frame, _) = gpu_frame(path, msaa, scalarize);
    assert!(
        frame.params.light_count > 30,
        "the frame culls its lights ({})",
        frame.params.light_count
    );
    let lit = frame
        .hdr
        .iter()
        .filter(|p| p[0] + p[1] + p[2] > 0.0)
        .count();
    assert!(lit > frame.hdr.len() / 2, "the frame is lit ({lit} pixels)");
    let shadowed = |bytes: &[u8]| {
        bytemuck::pod_collect_to_vec::<u8, GpuLight>(bytes)
            .iter()
            .filter(|l| l.shadow != NO_SHADOW)
            .count()
    };
    assert!(
        shadowed(&frame.lights) >= 4 && shadowed(&frame.directional) == 1,
        "the shadowed lights read the shadow atlas"
    );
    let c = compile(TBDR_SOURCE).expect("the TBDR module compiles");
    for &(subgroup_size, schedule) in runs {
        let started = std::time::Instant::now();
        let run = HostRun {
            subgroup_size,
            schedule,
            race_detection: true,
            unwritten_reads: true,
        };
        let host = host_shade(&c, axes, &frame, run)
            .unwrap_or_else(|e| panic!("{axes:?}, subgroup {subgroup_size}, {schedule:?}: {e}"));
        let (largest, off) = difference(&frame, &host.hdr, TOLERANCE);
        eprintln!(
            "host tbdr {axes:?} {WIDTH}×{HEIGHT}, subgroup {subgroup_size}, {schedule:?}: \
             {:.0} ms, largest relative difference {largest:.5}, {off} pixels off",
            started.elapsed().as_secs_f64() * 1e3
        );
        assert_eq!(off, 0, "{axes:?}, subgroup {subgroup_size}, {schedule:?}");
        let edges_differ: u32 = host
            .edge_bits
            .iter()
            .zip(&frame.record.edge_bits)
            .map(|(h, g)| (h ^ g).count_ones())
            .sum();
        assert_eq!(edges_differ, 0, "edge pixels, subgroup {subgroup_size}");
    }
}

#[test]
fn host_tbdr_scalarized_msaa4_equals_the_gpu_frame_at_four_subgroup_sizes() {
    check(
        &[("tile", 8), ("msaa", 4), ("scalarize", 1), ("defer", 0)],
        RenderPath::Tbdr,
        4,
        &[
            (4, Schedule::InOrder),
            (8, Schedule::Reversed),
            (32, Schedule::Shuffled(3)),
            (64, Schedule::Reversed),
        ],
    );
}

#[test]
fn host_tbdr_deferred_per_sample_and_plain_msaa1_equal_the_gpu_frames() {
    check(
        &[("tile", 8), ("msaa", 4), ("scalarize", 1), ("defer", 1)],
        RenderPath::TbdrPerSample,
        4,
        &[(8, Schedule::Shuffled(11)), (32, Schedule::InOrder)],
    );
    check(
        &[("tile", 8), ("msaa", 1), ("scalarize", 0), ("defer", 0)],
        RenderPath::Tbdr,
        1,
        &[(4, Schedule::Reversed)],
    );
}

#[test]
fn an_off_by_one_in_the_exclusive_add_is_caught() {
    let site = "let rank = subgroup_exclusive_add(one);";
    assert!(TBDR_SOURCE.contains(site), "the mutation site moved");
    let mutated =
        compile(&TBDR_SOURCE.replacen(site, "let rank = subgroup_inclusive_add(one);", 1))
            .expect("the mutation compiles");
    let axes = [("tile", 8), ("msaa", 4), ("scalarize", 1), ("defer", 0)];
    let (frame, _) = gpu_frame(RenderPath::Tbdr, 4, true);
    let read_line = TBDR_SOURCE
        .lines()
        .position(|l| l.contains("let mut index = LIST[j];"))
        .expect("the list read")
        + 1;
    let subgroup_size = 8;
    // The checks name the line that reads the slot the append skipped.
    let run = HostRun {
        subgroup_size,
        schedule: Schedule::InOrder,
        race_detection: true,
        unwritten_reads: true,
    };
    let err = host_shade(&mutated, &axes, &frame, run).expect_err("the hole is read");
    let text = err.to_string();
    assert!(matches!(err.cause(), EvalError::Unwritten(_)), "{text}");
    assert!(
        text.contains(&format!("LIST[0]` at {read_line}:")),
        "{text}"
    );
    eprintln!("subgroup {subgroup_size}: {text}");
    // Without them, the image is wrong.
    let unchecked = HostRun {
        race_detection: false,
        unwritten_reads: false,
        ..run
    };
    let host = host_shade(&mutated, &axes, &frame, unchecked).expect("the mutation runs");
    let (largest, off) = difference(&frame, &host.hdr, TOLERANCE);
    eprintln!(
        "subgroup {subgroup_size}: largest relative difference {largest:.3}, {off} pixels off"
    );
    assert!(off > 0, "subgroup {subgroup_size} hid the off-by-one");
}

#[test]
fn host_gbuffer_capture_and_depth_probes_equal_the_gpus() {
    let (frame, capture) = gpu_frame(RenderPath::Tbdr, 4, false);
    let tbdr = compile(TBDR_SOURCE).expect("the TBDR module compiles");
    let probe = codegen::compile_source(include_str!("../../shaders_gen/src/inspect.rs"))
        .expect("depth_probe compiles");
    let r = &frame.record;
    let depth: Vec<f32> = r
        .gbuffer
        .chunks_exact(shaders_gen::deferred::tbdr::CAPTURE_WORDS as usize)
        .map(|s| s[0])
        .collect();
    let surface = depth.iter().filter(|&&d| d < 1.0).count();
    assert!(
        surface > depth.len() / 2,
        "the frame has surfaces ({surface} samples)"
    );
    let runs = [
        (4, Schedule::Reversed),
        (8, Schedule::InOrder),
        (32, Schedule::Shuffled(4)),
        (64, Schedule::InOrder),
    ];
    let axes = [("tile", 8), ("msaa", 4), ("scalarize", 0), ("defer", 0)];
    for (subgroup_size, schedule) in runs {
        let run = HostRun {
            subgroup_size,
            schedule,
            race_detection: true,
            unwritten_reads: true,
        };
        // The capture is the G-buffer the GPU recorded with the same kernel: the same bits.
        let captured = host_capture(&tbdr, &axes, &frame, run).expect("host capture");
        let same = captured.len() == r.gbuffer.len()
            && captured
                .iter()
                .zip(&r.gbuffer)
                .all(|(h, g)| h.to_bits() == g.to_bits());
        assert!(same, "capture, subgroup {subgroup_size}");

        // The probes read the same depth samples the GPU's probe pass read.
        let env = tests::cull_interp::variant(&probe, &[("msaa", 4)]);
        let mut d = codegen::interp::Dispatch::new(&probe.module, env, "probe")
            .and_then(|d| d.with_subgroup_size(subgroup_size))
            .expect("dispatch")
            .with_schedule(schedule)
            .with_unwritten_read_check(true);
        let params = ProbeParams::new(
            glam::UVec2::new(r.width, r.height),
            capture.grid,
            capture.stride,
        );
        d.set_buffer("PARAMS", bytemuck::bytes_of(&params))
            .expect("params");
        d.set_buffer("PROBES", &vec![0; capture.probes.len() * 4])
            .expect("probes");
        d.set_texture(
            "DEPTH_MS",
            codegen::interp::HostTexture::depth(r.width, r.height, r.msaa, &depth),
        )
        .expect("depth");
        d.run([capture.grid.x.div_ceil(8), capture.grid.y.div_ceil(8), 1])
            .expect("host probes");
        let probes: Vec<f32> = bytemuck::pod_collect_to_vec(&d.buffer("PROBES").expect("probes"));
        assert_eq!(
            probes, capture.probes,
            "depth probes, subgroup {subgroup_size}"
        );
    }
    eprintln!(
        "capture of {} samples and {} depth probes equal at four subgroup sizes",
        depth.len(),
        capture.probes.len()
    );
}
