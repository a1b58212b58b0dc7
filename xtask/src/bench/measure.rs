//! Measuring one cell: warm-up frames, then timed frames back to back (at most one frame in
//! flight ahead of the CPU), each after the cell's own change of scene (moved lights, a moved
//! object, or none); per-pass GPU timestamps, the CPU time of the frame graph and of shadow
//! planning, and the overflow counters. Then one captured frame for the cull efficiency.
//!
//! A pass that a frame skipped (the shadow pass when nothing changed) counts as 0 ms in that
//! frame, so its median is the cost per frame, not per frame that ran it.

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use anyhow::{Result, ensure};
use renderer::frame::capture::SurfaceProbe;
use renderer::frame::{FrameCamera, Renderer};
use renderer::graph::PassTiming;
use renderer::shadow::ShadowReport;

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
    pub fn from(mut v: Vec<f64>) -> Self {
        v.sort_by(f64::total_cmp);
        Self(v)
    }

    pub fn median(&self) -> Option<f64> {
        (!self.0.is_empty()).then(|| percentile(&self.0, 0.5))
    }

    pub fn p90(&self) -> Option<f64> {
        (!self.0.is_empty()).then(|| percentile(&self.0, 0.9))
    }

    pub fn max(&self) -> Option<f64> {
        self.0.last().copied()
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
    /// CPU ms to finish and submit the frame's commands.
    pub cpu_submit_ms: Samples,
    /// CPU ms of shadow planning (empty without a shadow pass).
    pub shadow_cpu_ms: Samples,
    /// The shadow pass's report of the last timed frame.
    pub shadows: Option<ShadowReport>,
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

/// What changes before frame `n` of a cell (`n` counts warm-up frames too).
pub type Advance<'a> = dyn FnMut(&mut Renderer, u32) -> Result<()> + 'a;

/// Renders the cell's frames, each after `advance`, and collects their figures.
pub fn measure(
    renderer: &mut Renderer,
    target: &wgpu::Texture,
    camera: &FrameCamera,
    advance: &mut Advance<'_>,
    plan: FramePlan,
) -> Result<Measured> {
    let mut frame = 0u32;
    let mut dropped = 0;
    let mut render = |renderer: &mut Renderer, frame: &mut u32| -> Result<_> {
        advance(renderer, *frame)?;
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
    let mut submit = Vec::new();
    let mut shadow_cpu = Vec::new();
    let mut shadows = None;
    let mut note = String::new();
    let timed = Instant::now();
    let mut rendered = 0;
    while rendered < plan.frames {
        let report = render(renderer, &mut frame)?;
        rendered += 1;
        cpu.push(report.cpu_graph_ms);
        upload.push(report.cpu_upload_ms);
        submit.push(report.cpu_submit_ms);
        if let Some(s) = report.shadows {
            shadow_cpu.push(s.cpu_plan_ms);
            shadows = Some(s);
        }
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
    // The renderer sizes its lists before every frame; a drop means the lists outgrew one
    // storage binding, and a frame with missing lights is not a frame worth timing.
    ensure!(
        dropped == 0,
        "light culling dropped {dropped} list entries in timed frames ({} requested): the lists \
         outgrow one storage binding here; use the clustered or 2.5D path, smaller radii or fewer \
         lights",
        counters.map_or(0, |c| c.requested_entries)
    );
    let (passes, total) = per_pass(&timings);
    Ok(Measured {
        passes: passes
            .into_iter()
            .map(|(k, v)| (k, Samples::from(v)))
            .collect(),
        total: Samples::from(total),
        cpu_graph_ms: Samples::from(cpu),
        cpu_upload_ms: Samples::from(upload),
        cpu_submit_ms: Samples::from(submit),
        shadow_cpu_ms: Samples::from(shadow_cpu),
        shadows,
        frames: timings.len() as u32,
        dropped,
        requested_entries: counters.map_or(0, |c| c.requested_entries),
        note,
        wall_per_frame,
    })
}

/// GPU ms per pass over `frames` (0 in a frame that skipped a pass some other frame ran), and
/// the sum of all passes per frame.
fn per_pass(frames: &[Vec<PassTiming>]) -> (BTreeMap<String, Vec<f64>>, Vec<f64>) {
    let mut passes: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    for t in frames.iter().flatten() {
        passes.entry(t.pass.clone()).or_default();
    }
    for frame in frames {
        for (name, samples) in &mut passes {
            samples.push(
                frame
                    .iter()
                    .filter(|t| &t.pass == name)
                    .map(|t| t.gpu_ms)
                    .sum(),
            );
        }
    }
    let total = frames
        .iter()
        .map(|f| f.iter().map(|t| t.gpu_ms).sum())
        .collect();
    (passes, total)
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
