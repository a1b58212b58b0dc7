//! `cargo xtask bench-particles`: GPU time of the particle pipeline built so far, per frame, at
//! full pools of 10k to 1M particles: one fixed simulation step (update, spawn, compact), the
//! lighting atlas's layout (sizing, plan, allocation, sort keys) and the back-to-front bitonic
//! sort. Medians over many frames, from GPU timestamps. With `--lighting`, whole frames of the
//! demo scene: atlas against per-pixel particle lighting (`bench_particle_lighting`).

use std::path::PathBuf;

use anyhow::Result;
use glam::Vec3;
use renderer::frame::framing_camera;
use renderer::graph::PassEncoder;
use renderer::particles::{ParticleSystem, dust, smoke, sparks};
use renderer::passes::particles::{GpuSort, ParticleAtlas, ParticleSimulation};
use renderer::scene::Aabb;
use renderer::{GpuContext, GpuOptions};
use wgpu_profiler::{GpuProfiler, GpuProfilerSettings};

use crate::bench::calibrate::percentile;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Pool sizes (comma-separated); each is filled before timing.
    #[arg(long, value_delimiter = ',', default_value = "10000,100000,1000000")]
    pub counts: Vec<u32>,
    /// Timed frames per size.
    #[arg(long, default_value_t = 200)]
    pub frames: u32,
    /// Where the Markdown table goes.
    #[arg(long, default_value = "target/bench-particles")]
    pub out: PathBuf,
    /// Adapter name substring (as RENDERER_ADAPTER).
    #[arg(long)]
    pub adapter: Option<String>,
    /// Also time whole frames of the demo scene (1080p, MSAA 4, 4,096 lights, the camera in
    /// the smoke): atlas lighting against per-pixel lighting, with overdraw and image difference.
    #[arg(long)]
    pub lighting: bool,
    /// Timed frames per lighting and count with --lighting.
    #[arg(long, default_value_t = 30)]
    pub lighting_frames: u32,
    /// The culled path of the --lighting frames.
    #[arg(long, default_value = "clustered")]
    pub path: String,
    /// Frame size of the --lighting frames, WxH.
    #[arg(long, default_value = "1920x1080")]
    pub lighting_size: String,
    /// smoke | scene: the --lighting camera, close to the smoke (heavy overdraw) or the
    /// courtyard's own.
    #[arg(long, default_value = "smoke")]
    pub lighting_camera: String,
    /// Procedural lights of the --lighting frames.
    #[arg(long, default_value_t = 4096)]
    pub lighting_lights: usize,
}

/// Stages timed, in frame order.
const STAGES: [&str; 3] = ["simulate", "atlas layout", "sort"];

/// Smoke, sparks and dust in a 10 m room, each bearing the whole pool a second, so the pool
/// fills within a second and stays full (refused births are counted, as in any full pool).
fn system(capacity: u32) -> ParticleSystem {
    let rate = capacity as f32;
    ParticleSystem {
        emitters: vec![
            smoke(Vec3::new(-2.0, 0.0, 0.0), rate),
            sparks(Vec3::new(2.0, 0.5, 0.0), rate),
            dust(Vec3::new(0.0, 2.0, -1.0), rate),
        ],
        capacity,
        seed: 1,
    }
}

#[expect(clippy::print_stdout, reason = "command-line report")]
pub fn run(args: &Args) -> Result<()> {
    let options = GpuOptions::from_env().with_adapter_name(args.adapter.clone());
    let gpu = GpuContext::new_blocking(&options)?;
    anyhow::ensure!(
        gpu.capabilities().timestamp_inside_passes,
        "bench-particles needs TIMESTAMP_QUERY inside encoders; this adapter lacks it"
    );
    println!("adapter: {}", gpu.report());
    let mut table = String::from(
        "| particles | live | visible | simulate (µs) | atlas layout (µs) | sort (µs) | sort pairs | atlas side | shrink |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for &count in args.counts.iter().filter(|_| args.frames > 0) {
        let row = measure(&gpu, count, args.frames)?;
        println!("{row}");
        table.push_str(&row);
        table.push('\n');
    }
    if args.lighting {
        table.push('\n');
        let bench = crate::bench_particle_lighting::Bench {
            counts: args.counts.clone(),
            frames: args.lighting_frames,
            path: args.path.clone(),
            size: args.lighting_size.clone(),
            lights: args.lighting_lights,
            camera: args.lighting_camera.clone(),
        };
        table.push_str(&crate::bench_particle_lighting::table(&bench)?);
    }
    std::fs::create_dir_all(&args.out)?;
    let path = args.out.join("particles.md");
    std::fs::write(&path, &table)?;
    println!("wrote {}", path.display());
    Ok(())
}

fn measure(gpu: &GpuContext, count: u32, frames: u32) -> Result<String> {
    let sim = ParticleSimulation::new(gpu, system(count))?;
    let sort = GpuSort::new(gpu, count, wgpu::BufferUsages::empty())?;
    // Four times the cells the pool needs at 2×2 texels each (the largest side regions can address).
    let side = (ParticleAtlas::min_side(count) * 2).min(4096);
    let atlas = ParticleAtlas::new(gpu, &sim, &sort, side)?;
    let room = Aabb {
        min: Vec3::new(-5.0, 0.0, -5.0),
        max: Vec3::new(5.0, 5.0, 5.0),
    };
    let (width, height) = (1920, 1080);
    let camera = framing_camera(room, width as f32 / height as f32);
    // Fill the pool: the longest-lived emitter bears `count` a second.
    sim.advance(gpu, 90);
    let settings = GpuProfilerSettings {
        enable_debug_groups: false,
        ..Default::default()
    };
    let mut profiler =
        GpuProfiler::new(gpu.device(), settings).map_err(|e| anyhow::anyhow!("{e}"))?;
    let mut times: [Vec<f64>; 3] = Default::default();
    for _ in 0..frames {
        let mut encoder = gpu.device().create_command_encoder(&Default::default());
        {
            let mut scope = profiler.scope(STAGES[0], &mut encoder);
            sim.record_step(gpu.queue(), &mut PassEncoder::untimed(&mut scope));
        }
        {
            let mut scope = profiler.scope(STAGES[1], &mut encoder);
            atlas.record(gpu.queue(), &mut scope, &camera, height);
        }
        {
            let mut scope = profiler.scope(STAGES[2], &mut encoder);
            sort.record_in(&mut PassEncoder::untimed(&mut scope));
        }
        profiler.resolve_queries(&mut encoder);
        gpu.queue().submit([encoder.finish()]);
        profiler.end_frame().map_err(|e| anyhow::anyhow!("{e}"))?;
        gpu.wait_idle()?;
        for q in profiler
            .process_finished_frame(gpu.queue().get_timestamp_period())
            .unwrap_or_default()
        {
            let stage = STAGES.iter().position(|s| *s == q.label);
            if let (Some(i), Some(t)) = (stage, q.time) {
                times[i].push((t.end - t.start) * 1e6);
            }
        }
    }
    let counters = sim.read_counters(gpu)?;
    let report = atlas.read_report(gpu)?;
    let median = |t: &mut Vec<f64>| -> Result<f64> {
        anyhow::ensure!(!t.is_empty(), "no timestamps came back");
        t.sort_by(f64::total_cmp);
        Ok(percentile(t, 0.5))
    };
    Ok(format!(
        "| {count} | {} | {} | {:.1} | {:.1} | {:.1} | {} | {} | {} |",
        counters.alive,
        report.visible,
        median(&mut times[0])?,
        median(&mut times[1])?,
        median(&mut times[2])?,
        sort.count,
        atlas.side,
        report.shrink,
    ))
}
