//! The device's ceilings for the physical floor: copy bandwidth from a large buffer copy and
//! fp32 rate from an FMA-bound kernel, both timed with GPU timestamps
//! (`cargo xtask bench --calibrate`).
//!
//! The floor of a culling pass is the larger of the bytes it must move over the bandwidth (the
//! depth buffer, read once) and its sphere/plane tests over the FMA rate (every light against
//! every cell: six plane distances, [`FLOP_PER_SPHERE_TEST`]).

use anyhow::Result;
use renderer::GpuContext;
use serde::{Deserialize, Serialize};
use wgpu_profiler::{GpuProfiler, GpuProfilerSettings};

/// FLOP of one sphere-versus-frustum test (six plane distances, as in the brief's floor).
pub const FLOP_PER_SPHERE_TEST: f64 = 24.0;

/// Measured ceilings of a device.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Ceilings {
    /// Bytes read plus written per second by a buffer copy.
    pub bytes_per_s: f64,
    /// fp32 FLOP per second of an FMA-bound kernel.
    pub flop_per_s: f64,
}

impl Ceilings {
    /// Floor of a culling pass in µs: `depth_bytes` read once, `cells × lights` sphere tests.
    pub fn cull_floor_us(&self, depth_bytes: u64, cells: u64, lights: u64) -> f64 {
        let tests = cells as f64 * lights as f64;
        (depth_bytes as f64 / self.bytes_per_s).max(tests * FLOP_PER_SPHERE_TEST / self.flop_per_s)
            * 1e6
    }
}

/// The value at quantile `q` of sorted values (nearest rank).
pub fn percentile(sorted_times: &[f64], q: f64) -> f64 {
    let i = ((sorted_times.len() - 1) as f64 * q).round() as usize;
    sorted_times[i]
}

fn profiler(gpu: &GpuContext) -> Result<GpuProfiler> {
    let settings = GpuProfilerSettings {
        enable_debug_groups: false,
        ..Default::default()
    };
    GpuProfiler::new(gpu.device(), settings).map_err(|e| anyhow::anyhow!("{e}"))
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
        let mut encoder = gpu.device().create_command_encoder(&Default::default());
        {
            let mut scope = profiler.scope("timed", &mut encoder);
            record(&mut scope, frame);
        }
        profiler.resolve_queries(&mut encoder);
        gpu.queue().submit([encoder.finish()]);
        profiler.end_frame().map_err(|e| anyhow::anyhow!("{e}"))?;
        gpu.wait_idle()?;
        let results = profiler.process_finished_frame(gpu.queue().get_timestamp_period());
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

/// Copy bandwidth (bytes read + written per second) and FMA rate of the device.
pub fn calibrate(gpu: &GpuContext) -> Result<Ceilings> {
    let device = gpu.device();
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_floor_is_the_larger_of_bytes_and_tests() {
        // The brief's H100 figures: ~3 TB/s, ~50 TFLOP/s; 1080p, 16×16 tiles, 4,096 lights.
        let c = Ceilings {
            bytes_per_s: 3.0e12,
            flop_per_s: 50.0e12,
        };
        let tiles = 120 * 68;
        let depth = 1920 * 1080 * 4;
        let floor = c.cull_floor_us(depth, tiles, 4096);
        assert!((floor - 16.04).abs() < 0.01, "{floor} µs: tests bound it");
        assert!(
            (c.cull_floor_us(depth, tiles, 1) - 2.76).abs() < 0.01,
            "bytes bound it"
        );
        assert_eq!(c.cull_floor_us(0, 0, 0), 0.0);
    }

    #[test]
    fn percentiles_are_nearest_rank() {
        let v = [1.0, 2.0, 3.0, 4.0, 5.0];
        assert_eq!(percentile(&v, 0.5), 3.0);
        assert_eq!(percentile(&v, 0.9), 5.0);
        assert_eq!(percentile(&[7.0], 0.9), 7.0);
    }
}
