//! Measuring one cell: warm-up frames, then timed frames back to back (at most one frame in
//! flight ahead of the CPU), each with freshly moved lights; per-pass GPU timestamps, the CPU
//! time of the frame graph, and the overflow counters. Then one captured frame for the cull
//! efficiency.

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use anyhow::{Result, ensure};
use renderer::frame::capture::SurfaceProbe;
use renderer::frame::{FrameCamera, Renderer};
use renderer::graph::PassTiming;

use super::calibrate::percentile;
use super::lights::MovingLights;

/// How many frames a cell gets.
#[derive(Debug, Clone, Copy)]
pub struct FramePlan {
    pub warmup: u32,
    pub frames: u32,
    /// Wall time after which a cell stops early (noted in its record), once it has
    /// `min_frames`; warm-up gets a quarter of it.
    pub budget: Duration,
    pub min_frames: u32,
}

/// Sorted samples of one quantity.
#[derive(Debug, Clone, Default)]
pub struct Samples(Vec<f64>);

impl Samples {
    fn from(mut v: Vec<f64>) -> Self {
        v.sort_by(f64::total_cmp);
        Self(v)
    }

    pub fn median(&self) -> Option<f64> {
        (!self.0.is_empty()).then(|| percentile(&self.0, 0.5))
    }

    pub fn p90(&self) -> Option<f64> {
        (!self.0.is_empty()).then(|| percentile(&self.0, 0.9))
    }
}

/// What the timed frames of a cell gave.
#[derive(Debug, Clone)]
pub struct Measured {
    /// GPU ms per pass name.
    pub passes: BTreeMap<String, Samples>,
    /// GPU ms of all passes of a frame.
    pub total: Samples,
    pub cpu_graph_ms: Samples,
    pub cpu_upload_ms: Samples,
    /// Frames whose timestamps came back.
    pub frames: u32,
    /// Most list entries dropped in any measured frame.
    pub dropped: u32,
    /// Index-list entries the last measured frame requested.
    pub requested_entries: u32,
    /// Set when the budget cut the cell short.
    pub note: String,
    /// Wall time of one timed frame, for the next cell's estimate.
    pub wall_per_frame: Duration,
}

/// Renders the cell's frames and collects their figures.
pub fn measure(
    renderer: &mut Renderer,
    target: &wgpu::Texture,
    camera: &FrameCamera,
    lights: &MovingLights,
    plan: FramePlan,
) -> Result<Measured> {
    let mut frame = 0u32;
    let mut dropped = 0;
    let render = |renderer: &mut Renderer, frame: &mut u32| -> Result<_> {
        renderer.set_lights(&lights.at(*frame))?;
        *frame += 1;
        let report = renderer.render(camera, target)?;
        renderer.wait_for_frames_in_flight(1)?;
        Ok(report)
    };
    let started = Instant::now();
    for _ in 0..plan.warmup.max(1) {
        render(renderer, &mut frame)?;
        if started.elapsed() > plan.budget / 4 {
            break;
        }
    }
    // Timings of warm-up frames are dropped: everything collected from here on is timed.
    renderer.wait_for_frames_in_flight(0)?;
    drop(renderer.drain_timings());

    let mut timings: Vec<Vec<PassTiming>> = Vec::new();
    let mut cpu = Vec::new();
    let mut upload = Vec::new();
    let mut note = String::new();
    let timed = Instant::now();
    let mut rendered = 0;
    while rendered < plan.frames {
        let report = render(renderer, &mut frame)?;
        rendered += 1;
        cpu.push(report.cpu_graph_ms);
        upload.push(report.cpu_upload_ms);
        timings.extend(report.timings);
        timings.extend(renderer.drain_timings());
        if let Some(c) = report.culling {
            dropped = dropped.max(c.dropped);
        }
        if rendered >= plan.min_frames && rendered < plan.frames && timed.elapsed() > plan.budget {
            note = format!(
                "time budget: {rendered} of {} frames ({:.2} s each)",
                plan.frames,
                timed.elapsed().as_secs_f64() / f64::from(rendered)
            );
            break;
        }
    }
    let wall_per_frame = timed.elapsed() / rendered.max(1);
    renderer.wait_for_frames_in_flight(0)?;
    for _ in 0..100 {
        if timings.len() >= rendered as usize {
            break;
        }
        timings.extend(renderer.drain_timings());
        std::thread::sleep(Duration::from_millis(1));
    }
    ensure!(
        !timings.is_empty(),
        "no GPU timestamps came back (the adapter needs TIMESTAMP_QUERY)"
    );
    let counters = renderer.culling_counters();
    if let Some(c) = counters {
        dropped = dropped.max(c.dropped);
    }
    let mut passes: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    let mut total = Vec::new();
    for frame in &timings {
        for t in frame {
            passes.entry(t.pass.clone()).or_default().push(t.gpu_ms);
        }
        total.push(frame.iter().map(|t| t.gpu_ms).sum());
    }
    Ok(Measured {
        passes: passes
            .into_iter()
            .map(|(k, v)| (k, Samples::from(v)))
            .collect(),
        total: Samples::from(total),
        cpu_graph_ms: Samples::from(cpu),
        cpu_upload_ms: Samples::from(upload),
        frames: timings.len() as u32,
        dropped,
        requested_entries: counters.map_or(0, |c| c.requested_entries),
        note,
        wall_per_frame,
    })
}

/// Surface probes of a frame and the lights reaching each: the same for every culled path of a
/// scene, size, MSAA and light count, so computed once and reused.
#[derive(Debug, Clone)]
pub struct Reaching {
    pub surface: Vec<SurfaceProbe>,
    pub counts: Vec<u32>,
}

impl Reaching {
    /// Mean number of lights reaching a surface sample.
    pub fn mean(&self) -> f64 {
        self.counts.iter().map(|&c| f64::from(c)).sum::<f64>() / self.counts.len().max(1) as f64
    }
}

/// Renders one captured frame with the lights of frame 0 and returns the cull efficiency
/// (lights listed ÷ lights reaching, over the probed surface samples).
pub fn cull_efficiency(
    renderer: &mut Renderer,
    target: &wgpu::Texture,
    camera: &FrameCamera,
    lights: &MovingLights,
    stride: u32,
    reaching: &mut Option<Reaching>,
) -> Result<Option<f64>> {
    renderer.set_lights(&lights.at(0))?;
    renderer.capture_next_frame(stride)?;
    renderer.render(camera, target)?;
    let Some(capture) = renderer.take_capture()? else {
        return Ok(None);
    };
    let r = reaching.get_or_insert_with(|| {
        let surface = capture.surface_probes();
        let counts = capture.lights_reaching(&surface);
        Reaching { surface, counts }
    });
    Ok(capture
        .cull_efficiency(&r.surface, &r.counts)
        .map(|e| e.ratio()))
}
