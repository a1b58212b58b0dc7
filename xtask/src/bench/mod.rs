//! `cargo xtask bench`: every render path side by side, per pass, over a matrix of light counts,
//! sizes, MSAA counts, tile sizes and scalarization, with the culling pass set beside its
//! physical floor.
//!
//! Each cell renders warm-up frames, then timed frames back to back with moving lights, and
//! records per-pass GPU timestamps (median, p90), the CPU time of the frame graph, the light
//! list's bytes and, from one captured frame, the cull efficiency against the CPU reference. The
//! run writes `bench.csv` (one row per cell, written as it goes), `bench.md` and PNG charts.
//! `--report CSV` re-renders the Markdown and charts from a CSV, e.g. one from a GPU machine.
//!
//! `--shadowed 16,64,256` turns the run into the shadow benchmark: every set-up and light count
//! is measured with that many shadowed lights, per kind and per mode (static, one object moving,
//! every light moving, cache off), beside the same frame without shadows ([`shadows`]).
//!
//! `--decals 0,256,1024,4096` measures each cell of the light matrix again with that many
//! procedural decals, beside the same frame without ([`decals`]).
//!
//! Module map: [`matrix`] (axes → set-ups), [`lights`] (the moving light set), [`shadows`] (the
//! shadow axis), [`measure`] (frames of one cell), [`calibrate`] (ceilings and floors),
//! [`record`] (the CSV row), [`markdown`] and [`charts`] (reports).

pub mod calibrate;
pub(crate) mod charts;
pub(crate) mod decals;
mod lights;
mod markdown;
pub(crate) mod matrix;
mod measure;
mod record;
mod shadows;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context as _, Result};
use renderer::frame::setup::{create_target, default_camera};
use renderer::frame::{RenderPath, Renderer, RendererConfig};
use renderer::scene::Scene;
use renderer::{GpuContext, GpuOptions};

use matrix::{Axes, PathChoice, Setup, Support};
use measure::{FramePlan, Reaching};
use record::{CellRecord, CsvSink};
use shadows::{ShadowAxes, ShadowKind, ShadowMode};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Light counts (procedural point lights, plus the scene's own).
    #[arg(long, value_delimiter = ',', default_value = "1024,4096,16384,65536")]
    lights: Vec<u32>,
    /// Frame sizes, WxH.
    #[arg(long, value_delimiter = ',', default_value = "1920x1080,3840x2160")]
    sizes: Vec<String>,
    /// MSAA counts (those the adapter lacks are left out, and said so).
    #[arg(long, value_delimiter = ',', default_value = "1,2,4,8")]
    msaa: Vec<u32>,
    /// Paths: naive, naive-prez, tiled, 2.5d, clustered, tbdr, tbdr-per-sample, deferred.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "naive,naive-prez,tiled,2.5d,clustered"
    )]
    paths: Vec<String>,
    /// Tile sizes of the culled paths (tiled, 2.5D, and the clustered froxels' screen cells).
    #[arg(long, value_delimiter = ',', default_value = "8,16,32")]
    tiles: Vec<u32>,
    /// Culling levels: hierarchical (super-tiles, then tiles), brute-force (every tile tests
    /// every light), or both to compare.
    #[arg(long, value_delimiter = ',', default_value = "hierarchical")]
    cull: Vec<String>,
    /// Time each culling dispatch on its own (the `cull_depth/coarse/fine` columns); separate
    /// passes add to the culling total, so take totals from a run without it.
    #[arg(long)]
    cull_dispatch_times: bool,
    /// Scalarization: off, on (on needs SUBGROUP; left out without it).
    #[arg(long, value_delimiter = ',', default_value = "off,on")]
    scalarize: Vec<String>,
    /// glTF scenes measured after the built-in courtyard.
    #[arg(long)]
    scene: Vec<PathBuf>,
    /// Leave the built-in courtyard out (only the --scene files).
    #[arg(long)]
    no_demo_scene: bool,
    /// Timed frames per cell.
    #[arg(long, default_value_t = 30)]
    frames: u32,
    /// Untimed frames before them.
    #[arg(long, default_value_t = 2)]
    warmup: u32,
    /// Seconds of timed frames after which a cell stops early (its note says so); naive cells
    /// whose estimate exceeds twice this are skipped.
    #[arg(long, default_value_t = 1.2)]
    cell_budget: f64,
    /// Lights reaching a point of the light box on average (ranges shrink as counts grow).
    #[arg(long, default_value_t = 16.0)]
    light_density: f32,
    /// Seed of the lights.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Depth probes per captured frame for the cull efficiency.
    #[arg(long, default_value_t = 16_384)]
    probes: u32,
    /// Measure copy bandwidth and FMA rate first, for the floor column.
    #[arg(long)]
    calibrate: bool,
    /// Reduced sizes for software drivers (under 10 minutes on lavapipe): 256x144 and 384x216,
    /// lights 64, 256, 1024, 4096, 1 warm-up, 0.75 s of timed frames per cell.
    #[arg(long)]
    quick: bool,
    /// Run each scene × size × MSAA group in its own process, so memory a driver keeps per
    /// frame is returned between groups (lavapipe 22.3 keeps ~10 MB per frame in its queue
    /// thread). `--quick` turns it on.
    #[arg(long)]
    isolate: bool,
    /// Internal: run only this group (a child of `--isolate`).
    #[arg(long, hide = true)]
    group: Option<usize>,
    /// Internal: the parent's calibration, bytes/s and FLOP/s.
    #[arg(long, hide = true, value_delimiter = ',')]
    ceilings: Option<Vec<f64>>,
    /// Shadowed light counts: with it, the run is the shadow benchmark (each count of the
    /// procedural lights casts shadows, picked by screen influence; 0 adds the frame without
    /// shadows). Each count must be at most every --lights count.
    #[arg(long, value_delimiter = ',')]
    shadowed: Vec<u32>,
    /// What the shadowed lights are: point (six cube faces each), spot (pointing down).
    #[arg(long, value_delimiter = ',', default_value = "point,spot")]
    shadow_kinds: Vec<String>,
    /// What changes between frames: static (everything cached), moving (one dynamic object
    /// moves), lights-moving (every light moves), uncached (static, cache off).
    #[arg(long, value_delimiter = ',', default_value = "static,moving,uncached")]
    shadow_modes: Vec<String>,
    /// Decal counts: each cell of the light matrix with that many procedural decals on the
    /// scene's surfaces (0: none).
    #[arg(long, value_delimiter = ',', default_value = "0")]
    decals: Vec<u32>,
    /// Side of the shadow atlas in texels.
    #[arg(long, default_value_t = 8192)]
    shadow_atlas: u32,
    /// Output folder for bench.csv, bench.md and the charts.
    #[arg(long, default_value = "target/bench")]
    out: PathBuf,
    /// Only re-render bench.md and the charts from this CSV (no GPU needed).
    #[arg(long)]
    report: Option<PathBuf>,
    /// Adapter name substring (also RENDERER_ADAPTER).
    #[arg(long)]
    adapter: Option<String>,
}

pub fn run(args: &Args) -> Result<()> {
    let out = crate::workspace_root().join(&args.out);
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    if let Some(csv) = &args.report {
        let meta = std::fs::read_to_string(csv.with_file_name("meta.md")).unwrap_or_default();
        let records = record::read_csv(csv)?;
        write_markdown(&meta, &records, &out)?;
        return write_charts(&records, &out);
    }
    if cfg!(debug_assertions) && std::env::var_os("BENCH_ALLOW_DEBUG").is_none() {
        return rerun_in_release();
    }
    sweep(args, &out)
}

/// A benchmark of a debug build measures the debug build: re-run this command in release.
fn rerun_in_release() -> Result<()> {
    eprintln!("bench: building and running in release (set BENCH_ALLOW_DEBUG=1 to skip)");
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let status = std::process::Command::new(cargo)
        .args(["run", "--release", "--quiet", "--package", "xtask", "--"])
        .args(std::env::args_os().skip(1))
        .current_dir(crate::workspace_root())
        .status()
        .context("running cargo")?;
    anyhow::ensure!(status.success(), "the release benchmark failed ({status})");
    Ok(())
}

struct BenchScene {
    name: String,
    scene: Scene,
}

fn load_scenes(args: &Args) -> Result<Vec<BenchScene>> {
    let mut scenes = Vec::new();
    if !args.no_demo_scene {
        scenes.push(BenchScene {
            name: crate::render::BUILTIN_SCENE.to_string(),
            scene: renderer::scene::procedural::courtyard(),
        });
    }
    for p in &args.scene {
        let name = p
            .file_stem()
            .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
        scenes.push(BenchScene {
            name,
            scene: Scene::load(p)?,
        });
    }
    anyhow::ensure!(
        !scenes.is_empty(),
        "no scene: drop --no-demo-scene or give --scene FILE"
    );
    Ok(scenes)
}

fn axes(args: &Args, scenes: &[BenchScene]) -> Result<Axes> {
    let mut axes = Axes {
        scenes: scenes.iter().map(|s| s.name.clone()).collect(),
        sizes: parse_list(&args.sizes, matrix::parse_size)?,
        msaa: args.msaa.clone(),
        paths: parse_list(&args.paths, PathChoice::parse)?,
        tiles: args.tiles.clone(),
        scalarize: parse_list(&args.scalarize, matrix::parse_on_off)?,
        brute_force: parse_list(&args.cull, matrix::parse_cull)?,
        lights: args.lights.clone(),
    };
    if args.quick {
        axes.sizes = vec![(256, 144), (384, 216)];
        axes.lights = vec![64, 256, 1024, 4096];
    }
    for &t in &axes.tiles {
        anyhow::ensure!([8, 16, 32].contains(&t), "tile {t}: use 8, 16 or 32");
    }
    anyhow::ensure!(
        axes.lights.iter().all(|&n| n > 0),
        "light counts must be positive"
    );
    Ok(axes)
}

/// Every value of a list option, parsed; the first bad one is the error.
fn parse_list<T>(values: &[String], parse: impl Fn(&str) -> Result<T>) -> Result<Vec<T>> {
    values.iter().map(|v| parse(v)).collect()
}

/// The shadow axis; empty without `--shadowed`.
fn shadow_axes(args: &Args, axes: &Axes) -> Result<ShadowAxes> {
    let fewest = axes.lights.iter().copied().min().unwrap_or(0);
    for &n in &args.shadowed {
        anyhow::ensure!(
            n <= fewest,
            "--shadowed {n}: more than the {fewest} lights of --lights; give --lights {n} or more"
        );
    }
    Ok(ShadowAxes {
        counts: args.shadowed.clone(),
        kinds: parse_list(&args.shadow_kinds, ShadowKind::parse)?,
        modes: parse_list(&args.shadow_modes, ShadowMode::parse)?,
    })
}

/// The renderer configuration of a set-up.
fn renderer_config(args: &Args, setup: &Setup) -> RendererConfig {
    let mut config = RendererConfig {
        width: setup.width,
        height: setup.height,
        msaa: setup.msaa,
        path: setup.path.0,
        tile: setup.tile.max(8),
        scalarize: setup.scalarize,
        cull_brute_force: setup.brute_force,
        time_cull_dispatches: args.cull_dispatch_times,
        ..Default::default()
    };
    config.shadows.atlas_size = args.shadow_atlas;
    config
}

#[expect(clippy::print_stdout, reason = "command-line report")]
fn sweep(args: &Args, out: &Path) -> Result<()> {
    let scenes = load_scenes(args)?;
    let axes = axes(args, &scenes)?;
    let shadow_cells = shadows::cells(&shadow_axes(args, &axes)?);
    anyhow::ensure!(
        shadow_cells.is_empty() || args.decals == [0],
        "--decals and --shadowed are separate benchmarks: run them one at a time"
    );
    let options = GpuOptions::from_env().with_adapter_name(args.adapter.clone());
    let gpu = GpuContext::new_blocking(&options)?;
    let caps = gpu.capabilities().clone();
    anyhow::ensure!(
        caps.timestamp_inside_passes,
        "the benchmark needs TIMESTAMP_QUERY inside encoders; this adapter lacks it"
    );
    println!("adapter: {}", gpu.report);
    let support = Support {
        msaa: caps.msaa_counts(),
        subgroup: caps.subgroup.is_some(),
    };
    let (mut setups, left_out) = matrix::expand(&axes, &support);
    let groups = matrix::groups(&setups);
    if let Some(k) = args.group {
        setups.retain(|s| matrix::group_key(s) == groups[k]);
    } else {
        for l in &left_out {
            println!("left out: {l}");
        }
    }
    let ceilings = if let Some(c) = &args.ceilings {
        anyhow::ensure!(c.len() == 2, "--ceilings takes BYTES_PER_S,FLOP_PER_S");
        Some(calibrate::Ceilings {
            bytes_per_s: c[0],
            flop_per_s: c[1],
        })
    } else if args.calibrate {
        let c = calibrate::calibrate(&gpu)?;
        println!(
            "calibration: copy bandwidth {:.0} GB/s, FMA rate {:.2} TFLOP/s",
            c.bytes_per_s / 1e9,
            c.flop_per_s / 1e12
        );
        Some(c)
    } else {
        None
    };
    let plan = if args.quick {
        FramePlan {
            warmup: 1,
            frames: args.frames,
            budget: Duration::from_secs_f64(0.75),
            min_frames: 3,
        }
    } else {
        FramePlan {
            warmup: args.warmup,
            frames: args.frames,
            budget: Duration::from_secs_f64(args.cell_budget),
            min_frames: 3,
        }
    };
    let meta = meta(args, &gpu, ceilings, &left_out, &plan);
    if (args.isolate || args.quick) && args.group.is_none() {
        drop(gpu);
        return run_isolated(groups.len(), ceilings, &meta, out);
    }
    let csv_name = args
        .group
        .map_or_else(|| "bench.csv".to_string(), |k| format!("group-{k}.csv"));
    if args.group.is_none() {
        std::fs::write(out.join("meta.md"), &meta)?;
    }
    let mut csv = CsvSink::create(&out.join(&csv_name))?;
    let per_light_count = if shadow_cells.is_empty() {
        args.decals.len()
    } else {
        shadow_cells.len()
    };
    let cells = (setups.len() * axes.lights.len() * per_light_count) as u64;
    let bar =
        indicatif::ProgressBar::new(cells).with_style(indicatif::ProgressStyle::with_template(
            "{bar:40} {pos}/{len} cells, {elapsed_precise} elapsed, ETA {eta_precise}  {msg}",
        )?);
    let started = Instant::now();
    let mut records = Vec::new();
    let mut reaching: HashMap<(usize, u32, u32, u32, u32), Reaching> = HashMap::new();
    for setup in &setups {
        let bench_scene = &scenes[setup.scene];
        let config = renderer_config(args, setup);
        if !shadow_cells.is_empty() {
            for &n in &axes.lights {
                let lights = lights::MovingLights::new(
                    bench_scene.scene.bounds,
                    n as usize,
                    args.light_density,
                    args.seed,
                );
                for &cell in &shadow_cells {
                    bar.set_message(format!(
                        "{} {}x{} msaa{} {} {n} lights, {}",
                        bench_scene.name,
                        setup.width,
                        setup.height,
                        setup.msaa,
                        setup.path.name(),
                        cell.label()
                    ));
                    let record = shadows::measure_cell(
                        &gpu,
                        (&bench_scene.name, &bench_scene.scene),
                        setup,
                        &lights,
                        cell,
                        config,
                        plan,
                    )?;
                    csv.push(&record)?;
                    records.push(record);
                    bar.inc(1);
                }
            }
            continue;
        }
        let mut renderer = Renderer::new(&gpu, config)?;
        renderer.prepare_scene(&bench_scene.scene)?;
        let target = create_target(&gpu.device, &config);
        let camera = default_camera(&bench_scene.scene, setup.width as f32 / setup.height as f32);
        let mut previous: Option<(u32, Duration)> = None;
        for &n in &axes.lights {
            let lights = lights::MovingLights::new(
                bench_scene.scene.bounds,
                n as usize,
                args.light_density,
                args.seed,
            );
            for &d in &args.decals {
                renderer.set_decals(&decals::decal_set(&bench_scene.scene, d, args.seed))?;
                let mut record = CellRecord::empty(&bench_scene.name, setup, n);
                record.decals = d;
                bar.set_message(format!(
                    "{} {}x{} msaa{} {} {n} lights {d} decals",
                    record.scene,
                    record.width,
                    record.height,
                    record.msaa,
                    record.label()
                ));
                let estimate = previous.map(|(m, wall)| wall.mul_f64(f64::from(n) / f64::from(m)));
                let naive = !setup.path.0.has_prepass() || setup.path.0 == RenderPath::NaivePrez;
                match estimate.filter(|e| naive && *e * (plan.min_frames + 1) > plan.budget * 2) {
                    Some(e) => {
                        record.note = format!(
                            "skipped: about {:.1} s per frame (estimated from {} lights); raise \
                         --cell-budget to run it",
                            e.as_secs_f64(),
                            previous.map_or(0, |p| p.0)
                        );
                    }
                    None => {
                        let mut advance = |r: &mut Renderer, frame: u32| -> Result<()> {
                            Ok(r.set_lights(&lights.at(frame))?)
                        };
                        let m =
                            measure::measure(&mut renderer, &target, &camera, &mut advance, plan)?;
                        previous = Some((n, m.wall_per_frame));
                        record.fill(&m, &renderer);
                        // The deferred paths cull in workgroup memory: no lists to measure.
                        let culled = setup.path.0.is_culled() && !setup.path.0.is_deferred();
                        // Cull efficiency is a property of the lights: measured once, without decals.
                        if culled && d == args.decals[0] {
                            let stride = probe_stride(setup.width, setup.height, args.probes);
                            let key = (setup.scene, setup.width, setup.height, setup.msaa, n);
                            let mut cached = reaching.remove(&key);
                            record.cull_efficiency = measure::cull_efficiency(
                                &mut renderer,
                                &target,
                                &camera,
                                &lights,
                                stride,
                                &mut cached,
                            )?;
                            record.lights_reaching_mean = cached.as_ref().map(Reaching::mean);
                            if let Some(c) = cached {
                                reaching.insert(key, c);
                            }
                            let culler = renderer.culler();
                            let depth_bytes = if culler.reads_depth() {
                                u64::from(setup.width * setup.height * setup.msaa) * 4
                            } else {
                                0
                            };
                            let cells = culler.lists().map_or(0, |l| u64::from(l.cells));
                            record.cull_floor_us = ceilings.map(|c| {
                                c.cull_floor_us(depth_bytes, cells, u64::from(record.lights))
                            });
                        }
                    }
                }
                csv.push(&record)?;
                records.push(record);
                bar.inc(1);
            }
        }
    }
    bar.finish_and_clear();
    println!(
        "{} cells in {:.0} s; wrote {}",
        records.len(),
        started.elapsed().as_secs_f64(),
        out.join(&csv_name).display()
    );
    if args.group.is_some() {
        return Ok(());
    }
    write_markdown(&meta, &records, out)?;
    // The CSV is the result; charts need a font, which a bare GPU machine may lack.
    if let Err(e) = write_charts(&records, out) {
        eprintln!("charts not drawn: {e:#}\nre-render them elsewhere with --report bench.csv");
    }
    Ok(())
}

/// Runs every group in a child process of this binary (same arguments plus `--group K` and the
/// calibration), then merges their CSVs into `bench.csv` and writes the reports.
#[expect(clippy::print_stdout, reason = "command-line report")]
fn run_isolated(
    groups: usize,
    ceilings: Option<calibrate::Ceilings>,
    meta: &str,
    out: &Path,
) -> Result<()> {
    let started = Instant::now();
    std::fs::write(out.join("meta.md"), meta)?;
    let exe = std::env::current_exe().context("finding this executable")?;
    let mut csv = CsvSink::create(&out.join("bench.csv"))?;
    let mut records = Vec::new();
    for k in 0..groups {
        println!("group {} of {groups} (own process)", k + 1);
        let mut child = std::process::Command::new(&exe);
        child
            .args(std::env::args_os().skip(1))
            .args(["--group", &k.to_string()]);
        if let Some(c) = ceilings {
            child.arg(format!("--ceilings={},{}", c.bytes_per_s, c.flop_per_s));
        }
        let status = child.status().context("starting a group's process")?;
        anyhow::ensure!(status.success(), "group {k} failed ({status})");
        let part = out.join(format!("group-{k}.csv"));
        for record in record::read_csv(&part)? {
            csv.push(&record)?;
            records.push(record);
        }
        std::fs::remove_file(&part)?;
    }
    println!(
        "{} cells in {:.0} s; wrote {}",
        records.len(),
        started.elapsed().as_secs_f64(),
        out.join("bench.csv").display()
    );
    write_markdown(meta, &records, out)?;
    if let Err(e) = write_charts(&records, out) {
        eprintln!("charts not drawn: {e:#}\nre-render them elsewhere with --report bench.csv");
    }
    Ok(())
}

#[expect(clippy::print_stdout, reason = "command-line report")]
fn write_markdown(meta: &str, records: &[CellRecord], out: &Path) -> Result<()> {
    let md = out.join("bench.md");
    std::fs::write(&md, markdown::report(meta, records))
        .with_context(|| format!("writing {}", md.display()))?;
    println!("wrote {}", md.display());
    Ok(())
}

#[expect(clippy::print_stdout, reason = "command-line report")]
fn write_charts(records: &[CellRecord], out: &Path) -> Result<()> {
    for png in charts::write_charts(records, out)? {
        println!("wrote {}", png.display());
    }
    Ok(())
}

/// Pixels between depth probes so that about `probes` probes cover the frame.
fn probe_stride(width: u32, height: u32, probes: u32) -> u32 {
    let area = f64::from(width) * f64::from(height);
    ((area / f64::from(probes.max(1))).sqrt().ceil() as u32).max(1)
}

/// The run's header: adapter, driver, date, command, calibration, frame plan.
fn meta(
    args: &Args,
    gpu: &GpuContext,
    ceilings: Option<calibrate::Ceilings>,
    left_out: &[String],
    plan: &FramePlan,
) -> String {
    let date = std::process::Command::new("date")
        .args(["-u", "+%Y-%m-%d %H:%M UTC"])
        .output()
        .ok()
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map_or_else(|| "unknown".into(), |s| s.trim().to_string());
    let command: Vec<String> = std::env::args().skip(1).collect();
    let mut s = format!(
        "## Run of {date}\n\n- Command: `cargo xtask {}`\n- Adapter: `{}`\n- Driver: `{} {}`\n\
         - Frames: {} warm-up, {} timed per cell (stopping early after {:.2} s, at least {}); \
         light density {} (lights reaching a point on average), seed {}\n",
        command.join(" "),
        gpu.report.name,
        gpu.report.driver,
        gpu.report.driver_info,
        plan.warmup,
        plan.frames,
        plan.budget.as_secs_f64(),
        plan.min_frames,
        args.light_density,
        args.seed
    );
    if let Some(c) = ceilings {
        s += &format!(
            "- Calibration: copy bandwidth {:.0} GB/s, FMA rate {:.2} TFLOP/s (floor = max(depth \
             bytes ÷ bandwidth, cells × lights × {} FLOP ÷ FMA rate))\n",
            c.bytes_per_s / 1e9,
            c.flop_per_s / 1e12,
            calibrate::FLOP_PER_SPHERE_TEST
        );
    }
    for l in left_out {
        s += &format!("- Left out: {l}\n");
    }
    s
}
