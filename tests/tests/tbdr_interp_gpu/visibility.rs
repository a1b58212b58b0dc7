//! `vis_shade`, the visibility path's materials-and-lighting kernel (glTF PBR's: the
//! `forward` material module's variant of the frame's `msaa` axis, `vis_frame` around
//! `gltf_surface`), run by the DSL's host
//! interpreter on exactly what a lavapipe frame bound (`tests::host_replay`: the triangle IDs of
//! every sample, the scene's index and vertex streams, draw and material records, the material
//! atlas, lights, clustered light lists, shadow atlas and views), against that frame's own
//! image: MSAA 1 and 4, scalarized and plain, at four subgroup sizes and three schedules. Edge
//! pixels (several triangles) are shaded once per triangle and weighted by coverage on both.
//!
//! The mutation: a kernel that gives a pixel's first triangle every sample (`vis_samples_of`
//! returning the samples left, not the ones that see its ID, so the pixel's other triangles
//! are never shaded) leaves the host's edge pixels unlike the GPU's, and no other pixel
//! changes.

use codegen::Compiled;
use codegen::interp::{Address, Compare, Dispatch, HostSampler, Schedule};
use renderer::frame::{RenderPath, Renderer, RendererConfig, VisibilityRaster, create_target};
use renderer::passes::visibility::VisShadePass;
use tests::gpu::gpu_test;
use tests::host_replay::{BindingsProbe, BoundInputs, rgba_texels};

use super::{HEIGHT, TOLERANCE, WIDTH, courtyard_frame, pixel_difference};

/// The kernel's module (`forward`, with `gltf_material`), as source text.
const GLTF_SOURCE: &str = include_str!("../../../shaders_gen/src/forward/shading.rs");
/// The visibility path's material frame, where the mutation goes.
const VIS_FRAME_SOURCE: &str = include_str!("../../../shaders_gen/src/visibility/frame.rs");
/// Every other library the kernel uses, as source text.
const LIBRARY_SOURCES: [&str; 14] = [
    include_str!("../../../shaders_gen/src/visibility/geometry.rs"),
    include_str!("../../../shaders_gen/src/visibility/blend.rs"),
    include_str!("../../../shaders_gen/src/visibility/samples64.rs"),
    include_str!("../../../shaders_gen/src/shared/samples.rs"),
    include_str!("../../../shaders_gen/src/forward/frame.rs"),
    include_str!("../../../shaders_gen/src/shared/material.rs"),
    include_str!("../../../shaders_gen/src/shared/atlas.rs"),
    include_str!("../../../shaders_gen/src/shared/lights.rs"),
    include_str!("../../../shaders_gen/src/shared/shadow.rs"),
    include_str!("../../../shaders_gen/src/shared/decal.rs"),
    include_str!("../../../shaders_gen/src/shared/camera.rs"),
    include_str!("../../../shaders_gen/src/shared/grid.rs"),
    include_str!("../../../shaders_gen/src/shared/brdf.rs"),
    include_str!("../../../shaders_gen/src/shared/normals.rs"),
];

/// The `forward` module compiled with `vis_frame` as `frame_source`.
fn compile(frame_source: &str) -> Compiled {
    let mut libraries = LIBRARY_SOURCES.to_vec();
    libraries.push(frame_source);
    let mut modules =
        codegen::compile_source_all_with(GLTF_SOURCE, &libraries).expect("the sources parse");
    let (name, compiled) = modules.swap_remove(0);
    assert_eq!(name, "forward", "the kernel's module");
    compiled.unwrap_or_else(|e| panic!("{name} does not compile: {e}"))
}

/// One lavapipe frame of the courtyard on the visibility path with the hardware raster (the
/// host replays the variant that reads its targets): what the shading kernel bound, its HDR
/// output among them.
fn gpu_frame(msaa: u32, scalarize: bool) -> BoundInputs {
    let (scene, lights, camera, config) = courtyard_frame(RenderPath::Visibility, msaa, scalarize);
    let config = RendererConfig {
        visibility_raster: VisibilityRaster::Hardware,
        ..config
    };
    gpu_test(|gpu| {
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        renderer.prepare_scene(&scene).expect("the scene fits");
        renderer.set_lights(&lights).expect("lights fit");
        let program = renderer
            .pass::<VisShadePass>()
            .expect("the visibility path shades in compute")
            .program()
            .clone();
        renderer
            .insert_pass_after("visibility shading", Box::new(BindingsProbe::new(&program)))
            .expect("the probe joins the frame");
        let target = create_target(gpu.device(), &config);
        renderer.render(&camera, &target).expect("frame");
        renderer.finish();
        renderer
            .pass::<BindingsProbe>()
            .expect("the probe runs")
            .take(gpu)
            .expect("the kernel's bindings read back")
    })
}

/// The renderer's samplers (wgpu cannot report them): the atlas's bilinear clamp at level 0,
/// the shadow comparison (lit where the reference ≥ the texel: reversed Z), the decals' bilinear
/// clamp (the frame has no decals: its atlas is never sampled).
const SAMPLERS: [(&str, HostSampler); 3] = [
    (
        "ATLAS_SAMPLER",
        HostSampler {
            linear: true,
            address: Address::ClampToEdge,
            compare: None,
        },
    ),
    (
        "SHADOW_SAMPLER",
        HostSampler {
            linear: true,
            address: Address::ClampToEdge,
            compare: Some(Compare::GreaterEqual),
        },
    ),
    (
        "DECAL_SAMPLER",
        HostSampler {
            linear: true,
            address: Address::ClampToEdge,
            compare: None,
        },
    ),
];

/// The host's image of `c`'s variant `axes` over `frame`'s bindings.
fn host_image(
    c: &Compiled,
    axes: &[(&str, i64)],
    frame: &BoundInputs,
    subgroup_size: u32,
    schedule: Schedule,
) -> Vec<[f32; 4]> {
    let env = tests::cull_interp::variant(c, axes);
    let mut d = Dispatch::new(&c.module, env, "vis_shade")
        .and_then(|d| d.with_subgroup_size(subgroup_size))
        .expect("dispatch")
        .with_schedule(schedule)
        .with_race_detection(true)
        .with_unwritten_read_check(true);
    frame
        .bind(&mut d, &["ATLAS_COLOUR"], &["HDR_OUT"], &SAMPLERS)
        .expect("the frame's bindings");
    d.run([WIDTH.div_ceil(8), HEIGHT.div_ceil(8), 1])
        .unwrap_or_else(|e| panic!("{axes:?}, subgroup {subgroup_size}, {schedule:?}: {e}"));
    rgba_texels(&d.texture("HDR_OUT").expect("the host's image"))
}

/// The GPU's image, the pixels whose samples see more than one triangle, and the triangles
/// the frame's pixels see.
fn gpu_image(frame: &BoundInputs) -> (Vec<[f32; 4]>, usize, usize) {
    let hdr = frame.texture("HDR_OUT").expect("HDR_OUT was bound");
    let gpu = rgba_texels(&hdr.host(false).expect("HDR_OUT decodes"));
    // A new renderer's first frame: the ID target (loaded, not cleared) starts zeroed, so its
    // sky samples read 0 here.
    let ids = frame
        .texture("IDS")
        .or(frame.texture("IDS_MS"))
        .expect("the triangle IDs were bound");
    let words: Vec<u32> = bytemuck::pod_collect_to_vec(&ids.bytes);
    let pixels: Vec<&[u32]> = words.chunks_exact(ids.samples as usize).collect();
    let edges = pixels
        .iter()
        .filter(|s| s.iter().any(|&id| id != s[0]))
        .count();
    let mut triangles: Vec<u32> = words.iter().copied().filter(|&id| id != 0).collect();
    triangles.sort_unstable();
    triangles.dedup();
    (gpu, edges, triangles.len())
}

/// The host against the GPU on a frame of `msaa` samples, for each of `runs`; the frame.
fn check(msaa: u32, scalarize: bool, runs: &[(u32, Schedule)]) -> BoundInputs {
    let frame = gpu_frame(msaa, scalarize);
    let (gpu, edges, triangles) = gpu_image(&frame);
    let lit = gpu.iter().filter(|p| p[0] + p[1] + p[2] > 0.0).count();
    assert!(lit > gpu.len() / 2, "the frame is lit ({lit} pixels)");
    assert!(triangles > 50, "the frame sees {triangles} triangles");
    if msaa > 1 {
        assert!(edges > 100, "{edges} pixels see more than one triangle");
    }
    let c = compile(VIS_FRAME_SOURCE);
    let axes = [
        ("list", 2),
        ("msaa", i64::from(msaa)),
        ("scalarize", i64::from(scalarize)),
    ];
    for &(subgroup_size, schedule) in runs {
        let started = std::time::Instant::now();
        let host = host_image(&c, &axes, &frame, subgroup_size, schedule);
        let (largest, off) = pixel_difference(&gpu, &host, TOLERANCE);
        eprintln!(
            "host vis_shade MSAA {msaa}, scalarize {scalarize}, subgroup {subgroup_size}, \
             {schedule:?}: {:.0} ms, {triangles} triangles, {edges} edge pixels, largest \
             relative difference {largest:.5}, {off} pixels off",
            started.elapsed().as_secs_f64() * 1e3
        );
        assert_eq!(
            off, 0,
            "MSAA {msaa}, subgroup {subgroup_size}, {schedule:?}"
        );
    }
    frame
}

#[test]
fn host_vis_shade_msaa4_equals_the_gpu_frame_at_four_subgroup_sizes() {
    let _ = check(
        4,
        true,
        &[
            (4, Schedule::InOrder),
            (8, Schedule::Reversed),
            (32, Schedule::Shuffled(3)),
            (64, Schedule::Reversed),
        ],
    );
}

/// Plain MSAA 1 and 4; then the mutation, on the MSAA 4 frame.
#[test]
fn host_vis_shade_plain_equals_the_gpu_frames_and_a_kernel_that_drops_edge_coverage_does_not() {
    check(1, false, &[(8, Schedule::Shuffled(5))]);
    let frame = check(4, false, &[(32, Schedule::InOrder)]);
    let site = "        seen\n    }\n";
    assert!(VIS_FRAME_SOURCE.contains(site), "the mutation site moved");
    let mutated = compile(&VIS_FRAME_SOURCE.replacen(site, "        left\n    }\n", 1));
    let (gpu, edges, _) = gpu_image(&frame);
    let axes = [("list", 2), ("msaa", 4), ("scalarize", 0)];
    let host = host_image(&mutated, &axes, &frame, 8, Schedule::InOrder);
    let (largest, off) = pixel_difference(&gpu, &host, TOLERANCE);
    eprintln!(
        "the first triangle given every sample: largest relative difference {largest:.3}, {off} of {edges} edge \
         pixels off"
    );
    assert!(
        off > edges / 4,
        "the host hid the mutation ({off} pixels off)"
    );
}
