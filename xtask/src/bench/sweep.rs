//! The benchmark run: every cell of the matrix measured in this process, or each group of
//! cells in a child process of its own whose CSVs are merged; a debug build re-runs itself in
//! release first.

use std::collections::HashMap;
use std::path::Path;
use std::time::{Duration, Instant};

use anyhow::{Context as _, Result};
use renderer::extend::ComputeRasterPass;
use renderer::frame::{RenderPath, Renderer, VisibilityRaster};
use renderer::frame::{create_target, default_camera};
use renderer::{GpuContext, GpuOptions};

use super::edits;
use super::matrix::{self, Support};
use super::measure::{self, FramePlan, Reaching};
use super::options::{axes, load_scenes, renderer_config, shadow_axes};
use super::record::{self, CellRecord, CsvSink};
use super::reports::{meta, write_charts, write_markdown};
use super::{Args, calibrate, decals, lights, shadows};

pub fn run(args: &Args) -> Result<()> {
    let out = crate::workspace::workspace_root().join(&args.out);
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
        .current_dir(crate::workspace::workspace_root())
        .status()
        .context("running cargo")?;
    anyhow::ensure!(status.success(), "the release benchmark failed ({status})");
    Ok(())
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
    println!("adapter: {}", gpu.report());
    let support = Support {
        msaa: caps.msaa_counts(),
        subgroup: caps.subgroup.is_some(),
        int64_atomics: caps.int64_atomic_min_max,
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
                    bench_scene.light_box,
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
        if let Some(area) = args.compute_raster
            && config.path == RenderPath::Visibility
            && config.visibility_raster == VisibilityRaster::Hardware
        {
            let pass = ComputeRasterPass::new(&gpu, &config)?.with_small_area(area);
            renderer.insert_pass_after("visibility", Box::new(pass))?;
        }
        let target = create_target(gpu.device(), &config);
        let camera = default_camera(&bench_scene.scene, setup.width as f32 / setup.height as f32);
        let mut previous: Option<(u32, Duration)> = None;
        for &n in &axes.lights {
            let lights = lights::MovingLights::new(
                bench_scene.light_box,
                n as usize,
                args.light_density,
                args.seed,
            );
            for &d in &args.decals {
                renderer.set_decals(&decals::decal_set(&bench_scene.scene, d, args.seed))?;
                let mut record = CellRecord::empty(&bench_scene.name, setup, n);
                record.decals = d;
                record.instances = bench_scene.scene.instances.len() as u64;
                record.triangles = bench_scene.scene.triangle_count() as u64;
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
                        record.fill(&m, &mut renderer);
                        if let Some(pass) = renderer.pass::<ComputeRasterPass>() {
                            let c = pass.read_counts(&gpu)?;
                            let sep = if record.note.is_empty() { "" } else { "; " };
                            record.note += &format!(
                                "{sep}compute raster: {} large triangles in {} tiles, {} left out",
                                c.large, c.tiles, c.overflow
                            );
                        }
                        // Once per setup, after its first cell is timed.
                        if n == axes.lights[0] && d == args.decals[0] {
                            edits::measure(
                                &mut renderer,
                                &bench_scene.scene,
                                &target,
                                &camera,
                                &mut record,
                            )?;
                        }
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
                            let depth_bytes = u64::from(setup.width * setup.height * setup.msaa)
                                * u64::from(culler.depth_bytes_per_sample());
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
    // The CSV is the result: a chart that cannot be drawn or written does not fail the run.
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

/// Pixels between depth probes so that about `probes` probes cover the frame.
fn probe_stride(width: u32, height: u32, probes: u32) -> u32 {
    let area = f64::from(width) * f64::from(height);
    ((area / f64::from(probes.max(1))).sqrt().ceil() as u32).max(1)
}
