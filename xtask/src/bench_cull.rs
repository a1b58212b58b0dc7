//! `cargo xtask bench-cull`: GPU time of the light-culling kernels on a synthetic scene, beside
//! the physical floor. Lights move every frame (seeded), so no frame is a cached replay.
//!
//! For each method × tile size × scalarization × light count it records the culling pass's GPU
//! time (timestamps around the pass) over `--frames` frames after `--warmup`, and prints the
//! median and p90 in µs. `--calibrate` first measures the device's copy bandwidth and FMA rate;
//! the floor of a cell is then max(depth bytes ÷ bandwidth, sphere tests × 24 FLOP ÷ FMA rate).

use anyhow::{Context as _, Result};
use glam::{UVec2, Vec3};
use renderer::culling::clustered::{ClusterCullConfig, ClusteredCulling};
use renderer::culling::reference::ClusterGrid;
use renderer::culling::tiled::{TileCullConfig, TiledCulling};
use renderer::{GpuContext, GpuOptions};
use shaders_gen::culling::{cluster_cull, tile_cull};
use wgpu_profiler::{GpuProfiler, GpuProfilerSettings};

/// FLOP of one sphere-versus-frustum test (six plane distances, as in the brief's floor).
const FLOP_PER_SPHERE_TEST: f64 = 24.0;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Light counts.
    #[arg(long, value_delimiter = ',', default_value = "1024,4096,16384,65536")]
    lights: Vec<u32>,
    /// Target size, WxH.
    #[arg(long, default_value = "1920x1080")]
    size: String,
    /// MSAA samples of the depth buffer.
    #[arg(long, default_value_t = 1)]
    msaa: u32,
    /// Timed frames per cell.
    #[arg(long, default_value_t = 50)]
    frames: u32,
    /// Untimed frames before them.
    #[arg(long, default_value_t = 10)]
    warmup: u32,
    /// Measure copy bandwidth and FMA rate first, for the floor column.
    #[arg(long)]
    calibrate: bool,
    /// Small and fast (software drivers): 480x270, 1,024 and 4,096 lights, 10 frames.
    #[arg(long)]
    quick: bool,
    /// Adapter name substring (also RENDERER_ADAPTER).
    #[arg(long)]
    adapter: Option<String>,
}

/// One culling configuration of the sweep.
#[derive(Debug, Clone, Copy)]
enum Cell {
    Tiled {
        tile: u32,
        depth_mask: bool,
        scalarize: bool,
    },
    Clustered {
        scalarize: bool,
    },
}

#[derive(Debug, Clone, Copy)]
struct Ceilings {
    bytes_per_s: f64,
    flop_per_s: f64,
}

#[expect(clippy::print_stdout, reason = "command-line report")]
pub fn run(args: &Args) -> Result<()> {
    let (mut width, mut height) = parse_size(&args.size)?;
    let (mut lights, mut frames) = (args.lights.clone(), args.frames);
    if args.quick {
        (width, height, frames) = (480, 270, 10);
        lights = vec![1024, 4096];
    }
    let gpu =
        GpuContext::new_blocking(&GpuOptions::from_env().with_adapter_name(args.adapter.clone()))?;
    let caps = gpu.capabilities().clone();
    println!(
        "adapter: {} ({:?}), driver {} {}",
        gpu.report.name, gpu.report.backend, gpu.report.driver, gpu.report.driver_info
    );
    anyhow::ensure!(
        caps.timestamp_inside_passes,
        "bench-cull needs TIMESTAMP_QUERY inside encoders"
    );
    anyhow::ensure!(
        caps.msaa_depth32float.contains(&args.msaa),
        "MSAA {} is not supported here ({:?})",
        args.msaa,
        caps.msaa_depth32float
    );
    let ceilings = if args.calibrate {
        Some(calibrate(&gpu)?)
    } else {
        None
    };
    if let Some(c) = ceilings {
        println!(
            "calibration: copy bandwidth {:.0} GB/s, FMA rate {:.1} TFLOP/s",
            c.bytes_per_s / 1e9,
            c.flop_per_s / 1e12
        );
    }
    let scalar_options: &[bool] = if caps.subgroup.is_some() {
        &[false, true]
    } else {
        &[false]
    };
    let mut cells = Vec::new();
    for &scalarize in scalar_options {
        for tile in [8, 16, 32] {
            cells.push(Cell::Tiled {
                tile,
                depth_mask: false,
                scalarize,
            });
        }
        cells.push(Cell::Tiled {
            tile: 16,
            depth_mask: true,
            scalarize,
        });
        cells.push(Cell::Clustered { scalarize });
    }
    println!(
        "\n{width}x{height}, MSAA {}, {frames} timed frames after {} warm-up, GPU time of the culling pass",
        args.msaa, args.warmup
    );
    println!(
        "| method | tile | scalarize | lights | median µs | p90 µs | floor µs | median ÷ floor |"
    );
    println!("|---|---:|---|---:|---:|---:|---:|---:|");
    for &n in &lights {
        let scene = tests::cull_scene::scene(7, width, height, args.msaa, n as usize);
        let depth = tests::depth_upload::write_msaa_depth(
            &gpu,
            width,
            height,
            args.msaa,
            &scene.depth.depth,
        );
        let view = depth.create_view(&Default::default());
        for &cell in &cells {
            let times = time_cell(&gpu, cell, &scene, &view, args.msaa, args.warmup, frames)?;
            let (median, p90) = (percentile(&times, 0.5), percentile(&times, 0.9));
            let (name, tile, scalarize, cell_count) = match cell {
                Cell::Tiled {
                    tile,
                    depth_mask,
                    scalarize,
                } => {
                    let cells = u64::from(width.div_ceil(tile) * height.div_ceil(tile));
                    (
                        if depth_mask { "2.5D" } else { "tiled" },
                        tile.to_string(),
                        scalarize,
                        cells,
                    )
                }
                Cell::Clustered { scalarize } => {
                    ("clustered 16x8x24", "-".into(), scalarize, 16 * 8 * 24)
                }
            };
            let floor = ceilings.map(|c| {
                let bytes = f64::from(width * height * args.msaa * 4);
                let tests = cell_count as f64 * f64::from(n);
                (bytes / c.bytes_per_s).max(tests * FLOP_PER_SPHERE_TEST / c.flop_per_s) * 1e6
            });
            let (floor_s, ratio_s) = match floor {
                Some(f) => (format!("{f:.1}"), format!("{:.1}", median / f)),
                None => ("-".into(), "-".into()),
            };
            println!(
                "| {name} | {tile} | {} | {} | {median:.1} | {p90:.1} | {floor_s} | {ratio_s} |",
                if scalarize { "on" } else { "off" },
                scene.lights.len()
            );
        }
    }
    Ok(())
}

fn parse_size(s: &str) -> Result<(u32, u32)> {
    let (w, h) = s
        .split_once('x')
        .context("--size must be WxH, for example 1920x1080")?;
    Ok((w.parse().context("width")?, h.parse().context("height")?))
}

fn percentile(sorted_times: &[f64], q: f64) -> f64 {
    let i = ((sorted_times.len() - 1) as f64 * q).round() as usize;
    sorted_times[i]
}

fn profiler(gpu: &GpuContext) -> Result<GpuProfiler> {
    let settings = GpuProfilerSettings {
        enable_debug_groups: false,
        ..Default::default()
    };
    GpuProfiler::new(&gpu.device, settings).map_err(|e| anyhow::anyhow!("{e}"))
}

/// Runs `record` once per frame inside a profiler scope and returns the sorted GPU times in µs.
fn timed_frames(
    gpu: &GpuContext,
    warmup: u32,
    frames: u32,
    mut record: impl FnMut(&mut wgpu::CommandEncoder, u32),
) -> Result<Vec<f64>> {
    let mut profiler = profiler(gpu)?;
    let mut times = Vec::new();
    for frame in 0..warmup + frames {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        {
            let mut scope = profiler.scope("timed", &mut encoder);
            record(&mut scope, frame);
        }
        profiler.resolve_queries(&mut encoder);
        gpu.queue.submit([encoder.finish()]);
        profiler.end_frame().map_err(|e| anyhow::anyhow!("{e}"))?;
        gpu.wait_idle()?;
        let results = profiler.process_finished_frame(gpu.queue.get_timestamp_period());
        if frame >= warmup
            && let Some(t) = results.and_then(|r| r.into_iter().find_map(|q| q.time))
        {
            times.push((t.end - t.start) * 1e6);
        }
    }
    anyhow::ensure!(!times.is_empty(), "no timestamps came back");
    times.sort_by(f64::total_cmp);
    Ok(times)
}

fn time_cell(
    gpu: &GpuContext,
    cell: Cell,
    scene: &tests::cull_scene::CullScene,
    depth: &wgpu::TextureView,
    msaa: u32,
    warmup: u32,
    frames: u32,
) -> Result<Vec<f64>> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let n = scene.lights.len() as u32;
    let moved = |frame: u32| -> Vec<(Vec3, f32)> {
        let t = frame as f32 * 0.05;
        scene
            .lights
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let phase = i as f32 * 0.618;
                (
                    l.center + 0.5 * Vec3::new((t + phase).cos(), 0.0, (t + phase).sin()),
                    l.radius,
                )
            })
            .collect()
    };
    let (view, projection) = (scene.camera.view, scene.camera.projection);
    let index_capacity = renderer::culling::max_index_entries(&gpu.device).min(1 << 26);
    match cell {
        Cell::Tiled {
            tile,
            depth_mask,
            scalarize,
        } => {
            let config = TileCullConfig {
                tile,
                msaa,
                scalarize,
                depth_mask,
                include_transparent: false,
                max_per_tile: tile_cull::MAX_PER_TILE,
                index_capacity,
                item_capacity: n,
            };
            let culling = TiledCulling::new(gpu, config, w, h)?;
            timed_frames(gpu, warmup, frames, |encoder, frame| {
                let items: Vec<_> = moved(frame)
                    .into_iter()
                    .map(|(c, r)| tile_cull::CullSphere::new(c, r))
                    .collect();
                // Item counts never exceed the capacity set above.
                let _ = culling.upload(gpu, view, projection, UVec2::new(w, h), &items);
                culling.encode(&gpu.device, encoder, depth);
            })
        }
        Cell::Clustered { scalarize } => {
            let grid = ClusterGrid {
                x: 16,
                y: 8,
                z: 24,
                near: tests::cull_scene::NEAR,
                far: tests::cull_scene::FAR,
            };
            let config = ClusterCullConfig {
                grid,
                msaa,
                scalarize,
                skip_empty: true,
                max_per_cluster: cluster_cull::MAX_PER_CLUSTER,
                index_capacity,
                item_capacity: n,
            };
            let culling = ClusteredCulling::new(gpu, config, w, h)?;
            timed_frames(gpu, warmup, frames, |encoder, frame| {
                let items: Vec<_> = moved(frame)
                    .into_iter()
                    .map(|(c, r)| cluster_cull::CullSphere::new(c, r))
                    .collect();
                let _ = culling.upload(gpu, view, projection, &items);
                culling.encode(&gpu.device, encoder, depth);
            })
        }
    }
}

/// Copy bandwidth (bytes read + written per second) and FMA rate of the device.
fn calibrate(gpu: &GpuContext) -> Result<Ceilings> {
    let device = &gpu.device;
    let size = device.limits().max_buffer_size.min(1 << 30) / 2 * 2;
    let buffer = |usage| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("calibration"),
            size,
            usage,
            mapped_at_creation: false,
        })
    };
    let src = buffer(wgpu::BufferUsages::COPY_SRC);
    let dst = buffer(wgpu::BufferUsages::COPY_DST);
    let copy = timed_frames(gpu, 3, 10, |encoder, _| {
        encoder.copy_buffer_to_buffer(&src, 0, &dst, 0, size)
    })?;
    let bytes_per_s = 2.0 * size as f64 / (percentile(&copy, 0.5) * 1e-6);

    use shaders_gen::calibrate::fma_rate;
    let variant = fma_rate::variant(fma_rate::VariantKey::ALL[0]);
    let program = renderer::shader::ShaderProgram::new(device, gpu.capabilities(), variant)?;
    let pipeline = program.compute_pipeline(device, "fma_chains")?;
    let groups: u32 = 16_384;
    let threads = u64::from(groups) * u64::from(fma_rate::WORKGROUP);
    let sink = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("fma sink"),
        size: threads * 4,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &program.bind_group_layouts[0],
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: sink.as_entire_binding(),
        }],
    });
    let fma = timed_frames(gpu, 3, 10, |encoder, _| {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(groups, 1, 1);
    })?;
    let flop = threads as f64 * f64::from(fma_rate::ITERATIONS) * f64::from(fma_rate::CHAINS) * 2.0;
    Ok(Ceilings {
        bytes_per_s,
        flop_per_s: flop / (percentile(&fma, 0.5) * 1e-6),
    })
}
