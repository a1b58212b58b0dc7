//! The encoder a pass records into, and the compute and render passes it begins.
//!
//! Every pass of the frame graph is timed. Where the device can write timestamps between
//! commands (`TIMESTAMP_QUERY_INSIDE_ENCODERS`, native Vulkan, Metal and D3D12), the graph
//! brackets each pass with two; nothing here adds more. Where it cannot (WebGPU, whose timestamp
//! queries exist only at the bounds of a compute or render pass), each compute and render pass a
//! graph pass begins through [`PassEncoder`] carries its own `timestamp_writes`, nested under the
//! graph pass's scope, and [`super::PassTiming`] sums them into the graph pass's time.
//!
//! `cargo xtask check-invariants` rejects `begin_compute_pass` and `begin_render_pass` anywhere
//! in the renderer outside this file, so no pass escapes the timing through a raw
//! `wgpu::CommandEncoder`; on a `PassEncoder` those names are its own, timed, methods, so an
//! engine's pass written against wgpu's names is timed too.

use std::ops::{Deref, DerefMut};

use wgpu_profiler::{GpuProfiler, GpuProfilerQuery, ProfilerCommandRecorder};

/// Where a pass's compute and render passes put their timestamps.
#[derive(Clone, Copy)]
struct PassTimer<'a> {
    profiler: &'a GpuProfiler,
    /// The graph pass's own scope, the parent of each pass-level query.
    parent: &'a GpuProfilerQuery,
    /// Whether every compute and render pass carries timestamps (the device cannot write them
    /// between commands), or only those begun by [`PassEncoder::begin_compute_timed`].
    each_pass: bool,
}

/// The command encoder a pass records into. It dereferences to [`wgpu::CommandEncoder`] for
/// copies, clears and the like; compute and render passes begin through
/// [`PassEncoder::begin_compute`] and [`PassEncoder::begin_render`] (or wgpu's names,
/// `begin_compute_pass` and `begin_render_pass`, which this type's own methods shadow), which
/// time them where the device can only time whole passes.
pub struct PassEncoder<'a> {
    encoder: &'a mut wgpu::CommandEncoder,
    timer: Option<PassTimer<'a>>,
}

impl std::fmt::Debug for PassEncoder<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PassEncoder")
            .field("encoder", &self.encoder)
            .field("times_passes", &self.timer.is_some())
            .finish()
    }
}

impl<'a> PassEncoder<'a> {
    /// An encoder whose passes are not timed: for recording outside a frame graph (tools,
    /// tests, one-off uploads).
    pub fn untimed(encoder: &'a mut wgpu::CommandEncoder) -> Self {
        Self {
            encoder,
            timer: None,
        }
    }

    /// An encoder whose passes carry timestamps under `parent` when the device cannot write
    /// them between commands (and `profiler` has timer queries on).
    pub(super) fn for_graph_pass(
        encoder: &'a mut wgpu::CommandEncoder,
        device: &wgpu::Device,
        profiler: &'a GpuProfiler,
        parent: &'a GpuProfilerQuery,
    ) -> Self {
        let each_pass =
            times_each_pass(device.features(), profiler.settings().enable_timer_queries);
        Self {
            encoder,
            timer: Some(PassTimer {
                profiler,
                parent,
                each_pass,
            }),
        }
    }

    /// Whether the compute and render passes begun here carry their own timestamps.
    pub fn times_each_pass(&self) -> bool {
        self.timer.is_some_and(|t| t.each_pass)
    }

    /// Begins a compute pass named `label`.
    pub fn begin_compute(&mut self, label: &str) -> TimedPass<'_, wgpu::ComputePass<'_>> {
        let timed = self.times_each_pass();
        self.compute(label, timed)
    }

    /// Begins a compute pass named `label` that carries its own timestamps on every device
    /// with timestamp queries. Where the device also times between commands, frame timings list
    /// it under its label after its graph pass; where it times only whole passes (WebGPU), its
    /// time is part of its graph pass's sum. Outside a frame graph it is untimed like any other.
    pub fn begin_compute_timed(&mut self, label: &str) -> TimedPass<'_, wgpu::ComputePass<'_>> {
        self.compute(label, true)
    }

    /// [`PassEncoder::begin_compute`] under wgpu's name and descriptor, so that a pass written
    /// against `wgpu::CommandEncoder` (`ctx.encoder.begin_compute_pass(..)`) is timed too; the
    /// descriptor's `timestamp_writes` must be `None`.
    pub fn begin_compute_pass(
        &mut self,
        desc: &wgpu::ComputePassDescriptor<'_>,
    ) -> TimedPass<'_, wgpu::ComputePass<'_>> {
        assert!(
            desc.timestamp_writes.is_none(),
            "the pass encoder sets timestamp_writes"
        );
        self.begin_compute(desc.label.unwrap_or("compute pass"))
    }

    /// [`PassEncoder::begin_render`] under wgpu's name, so that a pass written against
    /// `wgpu::CommandEncoder` (`ctx.encoder.begin_render_pass(..)`) is timed too.
    pub fn begin_render_pass(
        &mut self,
        desc: &wgpu::RenderPassDescriptor<'_>,
    ) -> TimedPass<'_, wgpu::RenderPass<'_>> {
        self.begin_render(desc)
    }

    fn compute(&mut self, label: &str, timed: bool) -> TimedPass<'_, wgpu::ComputePass<'_>> {
        let query = if timed { self.pass_query(label) } else { None };
        let timestamp_writes = query
            .as_ref()
            .and_then(|(_, q)| q.compute_pass_timestamp_writes());
        let pass = self
            .encoder
            .begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label),
                timestamp_writes,
            });
        TimedPass { pass, query }
    }

    /// Begins a render pass as `desc` describes; its `timestamp_writes` must be `None`, as the
    /// timing is this encoder's to set.
    pub fn begin_render(
        &mut self,
        desc: &wgpu::RenderPassDescriptor<'_>,
    ) -> TimedPass<'_, wgpu::RenderPass<'_>> {
        assert!(
            desc.timestamp_writes.is_none(),
            "the pass encoder sets timestamp_writes"
        );
        let query = if self.times_each_pass() {
            self.pass_query(desc.label.unwrap_or("render pass"))
        } else {
            None
        };
        let timestamp_writes = query
            .as_ref()
            .and_then(|(_, q)| q.render_pass_timestamp_writes());
        let pass = self.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            timestamp_writes,
            ..desc.clone()
        });
        TimedPass { pass, query }
    }

    fn pass_query(&mut self, label: &str) -> Option<(&'a GpuProfiler, GpuProfilerQuery)> {
        let timer = self.timer?;
        let query = timer
            .profiler
            .begin_pass_query(label, &mut *self.encoder)
            .with_parent(Some(timer.parent));
        Some((timer.profiler, query))
    }
}

/// Whether a device with `features` needs timestamps on each compute and render pass to time
/// graph passes: it has timestamp queries but cannot write them between commands.
fn times_each_pass(features: wgpu::Features, timer_queries_on: bool) -> bool {
    timer_queries_on
        && features.contains(wgpu::Features::TIMESTAMP_QUERY)
        && !features.contains(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS)
}

impl Deref for PassEncoder<'_> {
    type Target = wgpu::CommandEncoder;
    fn deref(&self) -> &wgpu::CommandEncoder {
        self.encoder
    }
}

impl DerefMut for PassEncoder<'_> {
    fn deref_mut(&mut self) -> &mut wgpu::CommandEncoder {
        self.encoder
    }
}

/// A compute or render pass begun by a [`PassEncoder`]; it dereferences to the pass, and ends
/// its timestamp query (if any) when dropped, like the pass itself.
pub struct TimedPass<'p, P: ProfilerCommandRecorder> {
    pass: P,
    query: Option<(&'p GpuProfiler, GpuProfilerQuery)>,
}

impl<P: ProfilerCommandRecorder + std::fmt::Debug> std::fmt::Debug for TimedPass<'_, P> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TimedPass")
            .field("pass", &self.pass)
            .field("timed", &self.query.is_some())
            .finish()
    }
}

impl<P: ProfilerCommandRecorder> Deref for TimedPass<'_, P> {
    type Target = P;
    fn deref(&self) -> &P {
        &self.pass
    }
}

impl<P: ProfilerCommandRecorder> DerefMut for TimedPass<'_, P> {
    fn deref_mut(&mut self) -> &mut P {
        &mut self.pass
    }
}

impl<P: ProfilerCommandRecorder> Drop for TimedPass<'_, P> {
    fn drop(&mut self) {
        if let Some((profiler, query)) = self.query.take() {
            profiler.end_query(&mut self.pass, query);
        }
    }
}
