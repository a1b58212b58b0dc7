//! `cargo xtask demo`: the main job, and the first command a new user runs. It installs the
//! software Vulkan driver where it can, renders the built-in courtyard with 1,024 lights, 16 of
//! them and a moonlight casting shadows (640×360, MSAA 4 where supported, tiled Forward+), and
//! writes `target/demo/frame.png`, `target/demo/heatmap.png` (lights per pixel, with its legend),
//! `target/demo/shadow_atlas.png` (the shadow atlas, regions labelled), `target/demo/decals.png`
//! (decals per pixel: 96 procedural decals lie on the courtyard, applied before lighting),
//! `target/demo/particle_atlas.png` (the lighting atlas of 20,000 particles of smoke, sparks and
//! dust, lit once per frame and drawn blended in `frame.png`),
//! `target/demo/shading_frequency.png` (the same frame by tile-based deferred shading, the
//! pixels it shaded per sample in red), `target/demo/deferred.png` (the same frame by
//! traditional deferred shading, a light volume per light), `target/demo/visibility.png` and,
//! where the adapter has 64-bit atomics, `target/demo/visibility_compute.png` (the visibility
//! buffer path, rasterised by the hardware and by compute kernels), and `target/demo/graph.dot`
//! (the compiled frame graph), compares the deferred paths' frames and GPU times with Forward+'s,
//! then moves a sphere marked dynamic over
//! three frames and reports what the shadow cache redrew, with a summary of at most about 20
//! lines.

use anyhow::{Context as _, Result};
use glam::{Mat4, Vec3};
use renderer::demo::moving_instance;
use renderer::frame::create_target;
use renderer::frame::{FrameView, RenderPath, Renderer, RendererConfig, VisibilityRaster};
use renderer::scene::{LightKind, SceneLight};
use renderer::shadow::ShadowReport;

use crate::render::{Setup, Shot, save_png, save_text, setup, shadow_summary, shoot, shoot_with};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Use the adapter whose name contains this (case-insensitive); also `RENDERER_ADAPTER`.
    #[arg(long)]
    adapter: Option<String>,
    /// Exposure in stops (2^EV before the tonemap); defaults to the courtyard's calibrated 0.5.
    #[arg(long, allow_negative_numbers = true, value_parser = crate::render::parse_exposure)]
    exposure: Option<f32>,
    /// Output folder; defaults to target/demo.
    #[arg(long)]
    out_dir: Option<std::path::PathBuf>,
}

/// Procedural decals (scorch marks, stains, painted signs) on the courtyard's surfaces.
const DEMO_DECALS: usize = 96;
/// Particles of the built-in smoke, sparks and dust, lit through the lighting atlas.
const DEMO_PARTICLES: u32 = 20_000;

pub fn run(args: &Args) -> Result<()> {
    crate::system::ensure_vulkan_adapter()?;
    let render = crate::render::Args {
        scene: None,
        lights: 1024,
        shadowed: 16,
        shadow_atlas: 4096,
        seed: 1,
        decals: DEMO_DECALS,
        decals_file: None,
        particles: DEMO_PARTICLES,
        particle_lighting: "atlas".into(),
        vis_raster: "hardware".into(),
        particle_atlas: 1024,
        light_radius: None,
        path: "tiled".into(),
        msaa: 4,
        size: "640x360".into(),
        tile: 16,
        scalarize: "auto".into(),
        camera: None,
        eye: None,
        target: None,
        view: "lit".into(),
        exposure: args.exposure,
        ambient: None,
        out: None,
        adapter: args.adapter.clone(),
        msaa_fallback: true,
        no_cull_draws: false,
        no_occlusion: false,
    };
    let started = std::time::Instant::now();
    let mut s = setup(&render)?;
    s.lights.push(moonlight());
    let lit = shoot(&s, FrameView::Lit, true)?;
    let heat = shoot(&s, FrameView::Heatmap, false)?;
    let decal_heat = shoot(&s, FrameView::DecalHeatmap, false)?;
    let atlas = shoot(&s, FrameView::ShadowAtlas, false)?;
    let particle_atlas = shoot(&s, FrameView::ParticleAtlas, false)?;
    let frequency = RendererConfig {
        path: RenderPath::TbdrPerSample,
        view: FrameView::ShadingFrequency,
        ..s.config
    };
    let frequency = shoot_with(&s, frequency, false)?;
    let lit_by = |path| shoot_with(&s, RendererConfig { path, ..s.config }, false);
    let tbdr = lit_by(RenderPath::TbdrPerSample)?;
    let volumes = lit_by(RenderPath::Deferred)?;
    let visibility = lit_by(RenderPath::Visibility)?;
    // The visibility path with the compute rasteriser, where the adapter has 64-bit atomics.
    let compute = RendererConfig {
        path: RenderPath::Visibility,
        visibility_raster: VisibilityRaster::Compute,
        ..s.config
    };
    let compute = s.gpu.capabilities().int64_atomic_min_max.then_some(compute);
    let vis_compute = compute
        .map(|config| shoot_with(&s, config, false))
        .transpose()?;
    let mut timed: Vec<RendererConfig> = [
        s.config.path,
        RenderPath::TbdrPerSample,
        RenderPath::Deferred,
        RenderPath::Visibility,
    ]
    .map(|path| RendererConfig { path, ..s.config })
    .to_vec();
    timed.extend(compute);
    let warm_ms = timed
        .into_iter()
        .map(|config| warm_frame_ms(&s, config))
        .collect::<Result<Vec<_>>>()?;
    let moving = moving_sphere(&s)?;
    let dir = args
        .out_dir
        .clone()
        .unwrap_or_else(|| crate::workspace::workspace_root().join("target/demo"));
    let size = (s.config.width, s.config.height);
    let files = [
        dir.join("frame.png"),
        dir.join("heatmap.png"),
        dir.join("shadow_atlas.png"),
        dir.join("decals.png"),
        dir.join("particle_atlas.png"),
        dir.join("shading_frequency.png"),
        dir.join("deferred.png"),
        dir.join("visibility.png"),
        dir.join("graph.dot"),
        dir.join("visibility_compute.png"),
    ];
    save_png(&files[0], &lit.rgba, size)?;
    save_png(&files[1], &heat.rgba, size)?;
    save_png(&files[2], &atlas.rgba, size)?;
    save_png(&files[3], &decal_heat.rgba, size)?;
    save_png(&files[4], &particle_atlas.rgba, size)?;
    save_png(&files[5], &frequency.rgba, size)?;
    save_png(&files[6], &volumes.rgba, size)?;
    save_png(&files[7], &visibility.rgba, size)?;
    save_text(&files[8], &lit.graph_dot)?;
    let mut paths = vec![
        ("tbdr-per-sample", &tbdr),
        ("deferred", &volumes),
        ("visibility", &visibility),
    ];
    let files = match &vis_compute {
        Some(shot) => {
            save_png(&files[9], &shot.rgba, size)?;
            paths.push(("visibility, compute raster", shot));
            &files[..]
        }
        None => &files[..9],
    };
    summary(&s, &lit, files, started.elapsed().as_secs_f64());
    print_deferred(&lit, &paths, &warm_ms);
    if vis_compute.is_none() {
        print_no_compute_raster();
    }
    print_moving(&moving);
    Ok(())
}

/// Frames rendered before timing starts (pipelines compiled, caches and pools filled, the
/// shadow atlas drawn once).
const WARMUP_FRAMES: usize = 4;
/// Frames whose GPU time is taken; the median is printed.
const TIMED_FRAMES: usize = 9;

/// The median GPU time of a warm frame of `config` (every pass summed), over [`TIMED_FRAMES`]
/// frames after [`WARMUP_FRAMES`]; `None` without timestamp queries. Timed frames must list
/// every light.
fn warm_frame_ms(s: &Setup, config: RendererConfig) -> Result<Option<f64>> {
    let mut renderer = crate::render::renderer_for(s, config)?;
    let target = create_target(s.gpu.device(), &config);
    for _ in 0..WARMUP_FRAMES {
        renderer.render(&s.camera, &target)?;
    }
    renderer.wait_for_frames_in_flight(0)?;
    drop(renderer.drain_timings());
    let mut totals = Vec::new();
    for _ in 0..TIMED_FRAMES {
        renderer.render(&s.camera, &target)?;
        renderer.wait_for_frames_in_flight(0)?;
        totals.extend(
            renderer
                .drain_timings()
                .into_iter()
                .map(|t| t.iter().map(|p| p.gpu_ms).sum::<f64>()),
        );
    }
    if let Some(c) = renderer.culling_counters() {
        anyhow::ensure!(c.dropped == 0, "timed demo frames dropped list entries");
    }
    if totals.is_empty() {
        return Ok(None);
    }
    totals.sort_by(f64::total_cmp);
    Ok(Some(totals[totals.len() / 2]))
}

/// Says why the demo has no frame of the compute rasteriser.
#[expect(clippy::print_stdout, reason = "the demo's report")]
fn print_no_compute_raster() {
    println!("visibility, compute raster: not on this adapter (no SHADER_INT64_ATOMIC_MIN_MAX)");
}

/// The deferred paths' frames against Forward+'s `lit`: image difference, and the warm GPU
/// time of each path (`warm_ms`: Forward+, then `paths` in order).
#[expect(clippy::print_stdout, reason = "the demo's report")]
fn print_deferred(lit: &Shot, paths: &[(&str, &Shot)], warm_ms: &[Option<f64>]) {
    let time = |ms: Option<f64>| ms.map_or("no timestamps".into(), |ms| format!("{ms:.2} ms"));
    let cells: Vec<String> = paths
        .iter()
        .zip(&warm_ms[1..])
        .map(|((name, shot), &ms)| {
            let (mean, p99) = crate::render::difference(&lit.rgba, &shot.rgba);
            format!("{name} {} (differs by mean {mean:.2}, p99 {p99})", time(ms))
        })
        .collect();
    println!(
        "paths, median GPU time of {TIMED_FRAMES} warm frames after {WARMUP_FRAMES}: Forward+ {} | {}",
        time(warm_ms[0]),
        cells.join(" | ")
    );
}

/// A dim moonlight from above, casting the courtyard's long shadows (four cascades).
fn moonlight() -> SceneLight {
    SceneLight {
        kind: LightKind::Directional,
        position: Vec3::ZERO,
        direction: Vec3::new(0.5, -0.8, -0.35).normalize(),
        color: Vec3::new(0.65, 0.75, 1.0),
        intensity: 0.6,
        range: None,
        casts_shadow: true,
    }
}

/// Renders three frames of one renderer while a sphere, marked dynamic, moves between the
/// second and third: what the shadow cache did in each.
fn moving_sphere(s: &Setup) -> Result<[ShadowReport; 3]> {
    let mut renderer = Renderer::new(&s.gpu, s.config)?;
    renderer.prepare_scene(&s.scene)?;
    renderer.set_lights(&s.lights)?;
    let sphere = moving_instance(&s.scene).context("the courtyard has instances")?;
    let start = s.scene.instances[sphere].world_from_mesh;
    let sphere = renderer.scene_instance(sphere)?;
    renderer.set_instance_dynamic(sphere, true)?;
    let target = create_target(s.gpu.device(), &s.config);
    let mut reports = Vec::new();
    for offset in [0.0, 0.0, 0.6] {
        let moved = Mat4::from_translation(Vec3::new(0.0, offset, 0.0)) * start;
        renderer.set_instance_transform(sphere, moved)?;
        let report = renderer.render(&s.camera, &target)?;
        // Casts are counted on the GPU: the frame's own count, once it finished.
        renderer.finish();
        reports.push(
            renderer
                .shadow_report()
                .or(report.shadows)
                .unwrap_or_default(),
        );
    }
    reports
        .try_into()
        .map_err(|_| anyhow::anyhow!("three frames were rendered"))
}

#[expect(clippy::print_stdout, reason = "the demo's report")]
fn print_moving(frames: &[ShadowReport; 3]) {
    let line = |r: &ShadowReport| {
        let c = r.cache;
        format!(
            "{} redrawn, {} copied, {} untouched, {} draws",
            c.redrawn, c.copied, c.untouched, c.draws
        )
    };
    println!(
        "shadow cache with a moving sphere: first frame {} | same frame again {} | sphere moved {}",
        line(&frames[0]),
        line(&frames[1]),
        line(&frames[2])
    );
}

#[expect(clippy::print_stdout, reason = "the demo's report")]
fn summary(s: &Setup, shot: &Shot, files: &[std::path::PathBuf], secs: f64) {
    let c = &s.config;
    let name = &s.scene_name;
    println!(
        "demo: {name} ({} triangles), {} lights, {} decals, {}x{}, {:?} Forward+, MSAA {}, tile {}{}",
        s.scene.triangle_count(),
        s.lights.len(),
        s.decals.decals.len(),
        c.width,
        c.height,
        c.path,
        c.msaa,
        c.tile,
        if c.scalarize { ", scalarized" } else { "" },
    );
    let a = &s.gpu.report();
    println!(
        "adapter: {} ({:?}, {:?}), {} {}",
        a.name, a.backend, a.device_type, a.driver, a.driver_info
    );
    match &shot.timings {
        Some(t) => {
            let total: f64 = t.iter().map(|p| p.gpu_ms).sum();
            let cells: Vec<String> = t
                .iter()
                .map(|p| format!("{} {:.2}", p.pass, p.gpu_ms))
                .collect();
            println!("GPU ms: {} | total {total:.2}", cells.join(" | "));
        }
        None => println!("GPU ms: unavailable (the adapter has no timestamp queries)"),
    }
    if let Some(k) = shot.counters {
        let cells = c.width.div_ceil(c.tile) * c.height.div_ceil(c.tile);
        println!(
            "culling: {:.1} list entries (lights and decals) per tile on average, {} in the longest list, {} super-tiles fell back to testing every item, {} entries dropped",
            f64::from(k.requested_entries) / f64::from(cells.max(1)),
            k.max_cell_items,
            k.coarse_fallbacks,
            k.dropped,
        );
    }
    if let Some(r) = &shot.report.shadows {
        println!("{}", shadow_summary(r));
    }
    if let Some(p) = &shot.report.particles {
        println!("{}", crate::render::particle_summary(p));
    }
    if let Some(e) = shot.efficiency {
        println!(
            "cull efficiency: {e:.1} lights listed per light that reaches the sample (1.0 is perfect)"
        );
    }
    if let Some(d) = shot.report.scene_draws {
        println!("{}", crate::render::draws_line(&d));
    }
    println!(
        "CPU: prepare {:.2} ms, frame graph {:.2} ms, submit {:.2} ms",
        shot.report.cpu_upload_ms, shot.report.cpu_graph_ms, shot.report.cpu_submit_ms
    );
    for f in files {
        println!("wrote {}", f.display());
    }
    println!("done in {secs:.1} s");
}
