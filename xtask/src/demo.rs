//! `cargo xtask demo`: the main job, and the first command a new user runs. It installs the
//! software Vulkan driver where it can, renders the built-in courtyard with 1,024 lights (640×360,
//! MSAA 4 where supported, tiled Forward+), and writes `target/demo/frame.png`,
//! `target/demo/heatmap.png` (lights per pixel, with its legend) and `target/demo/graph.dot`
//! (the compiled frame graph), with a summary of at most about 20 lines.

use anyhow::Result;
use renderer::frame::FrameView;

use crate::render::{Setup, Shot, save_png, save_text, setup, shoot};

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

pub fn run(args: &Args) -> Result<()> {
    crate::system::ensure_vulkan_adapter()?;
    let render = crate::render::Args {
        scene: None,
        lights: 1024,
        shadowed: 16,
        shadow_atlas: 4096,
        seed: 1,
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
        out: None,
        adapter: args.adapter.clone(),
        msaa_fallback: true,
    };
    let started = std::time::Instant::now();
    let s = setup(&render)?;
    let lit = shoot(&s, FrameView::Lit, true)?;
    let heat = shoot(&s, FrameView::Heatmap, false)?;
    let dir = args
        .out_dir
        .clone()
        .unwrap_or_else(|| crate::workspace_root().join("target/demo"));
    let size = (s.config.width, s.config.height);
    let files = [
        dir.join("frame.png"),
        dir.join("heatmap.png"),
        dir.join("graph.dot"),
    ];
    save_png(&files[0], &lit.rgba, size)?;
    save_png(&files[1], &heat.rgba, size)?;
    save_text(&files[2], &lit.report.graph_dot)?;
    summary(&s, &lit, &files, started.elapsed().as_secs_f64());
    Ok(())
}

#[expect(clippy::print_stdout, reason = "the demo's report")]
fn summary(s: &Setup, shot: &Shot, files: &[std::path::PathBuf], secs: f64) {
    let c = &s.config;
    let name = &s.scene_name;
    println!(
        "demo: {name} ({} triangles), {} lights, {}x{}, {:?} Forward+, MSAA {}, tile {}{}",
        s.scene.triangle_count(),
        s.lights.len(),
        c.width,
        c.height,
        c.path,
        c.msaa,
        c.tile,
        if c.scalarize { ", scalarized" } else { "" },
    );
    let a = &s.gpu.report;
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
            "culling: {:.1} list entries per tile on average, {} in the longest list, {} super-tiles fell back to testing every light, {} entries dropped",
            f64::from(k.requested_entries) / f64::from(cells.max(1)),
            k.max_cell_items,
            k.coarse_fallbacks,
            k.dropped,
        );
    }
    if let Some(e) = shot.efficiency {
        println!(
            "cull efficiency: {e:.1} lights listed per light that reaches the sample (1.0 is perfect)"
        );
    }
    println!("CPU: frame graph {:.2} ms", shot.report.cpu_graph_ms);
    for f in files {
        println!("wrote {}", f.display());
    }
    println!("done in {secs:.1} s");
}
