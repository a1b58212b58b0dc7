//! What engines and tools ask of a running renderer besides frames: its passes (find one,
//! insert one), frame captures, culling counters, and GPU timings of frames in flight.

use super::{Culler, NO_CULLER, RenderError, Renderer, capture};
use crate::culling::lists::CullCounters;
use crate::frame_data::ConfigError;
use crate::graph::PassTiming;
use crate::passes::Pass;
use crate::passes::depth_probe::DepthProbePass;
use crate::passes::light_cull::LightCullPass;

impl Renderer {
    /// The names of the frame's passes, in order.
    pub fn pass_names(&self) -> Vec<&'static str> {
        self.passes.iter().map(|p| p.name()).collect()
    }

    /// Inserts `pass` right after the pass named `after` (an engine's own pass, or a debug
    /// view); it runs every frame from the next one on.
    pub fn insert_pass_after(
        &mut self,
        after: &str,
        pass: Box<dyn Pass>,
    ) -> Result<(), RenderError> {
        let at = self
            .passes
            .iter()
            .position(|p| p.name() == after)
            .ok_or_else(|| RenderError::Config(ConfigError::NoSuchPass(after.to_owned())))?;
        self.passes.insert(at + 1, pass);
        Ok(())
    }

    /// The frame's pass of type `P`, if it runs one.
    pub fn pass<P: Pass>(&self) -> Option<&P> {
        self.passes
            .iter()
            .find_map(|p| (p.as_ref() as &dyn std::any::Any).downcast_ref::<P>())
    }

    /// The frame's pass of type `P`, mutably.
    pub fn pass_mut<P: Pass>(&mut self) -> Option<&mut P> {
        self.passes
            .iter_mut()
            .find_map(|p| (p.as_mut() as &mut dyn std::any::Any).downcast_mut::<P>())
    }

    /// Asks the next frame to capture its depth at every `stride`-th pixel (both ways) and its
    /// light grid, for [`Self::take_capture`]. Needs the depth pre-pass.
    pub fn capture_next_frame(&mut self, stride: u32) -> Result<(), RenderError> {
        if self.pass::<DepthProbePass>().is_none() {
            return Err(RenderError::Config(ConfigError::CaptureNeedsDepth));
        }
        self.capture_request = Some(stride.max(1));
        Ok(())
    }

    /// Reads back the newest captured frame (blocking); `None` if no capture was rendered since
    /// the last call.
    pub fn take_capture(&mut self) -> Result<Option<capture::FrameCapture>, RenderError> {
        let pending = self
            .pass_mut::<DepthProbePass>()
            .and_then(DepthProbePass::take_pending);
        match pending {
            Some(p) => Ok(Some(p.read_back(&self.gpu)?)),
            None => Ok(None),
        }
    }

    /// Blocks until at most `max` submitted frames may still be running on the GPU, so a caller
    /// can keep the GPU busy without running ahead of the timestamp queries.
    pub fn wait_for_frames_in_flight(&mut self, max: usize) -> Result<(), RenderError> {
        while self.in_flight.len() > max {
            if let Some(index) = self.in_flight.pop_front() {
                self.gpu
                    .device()
                    .poll(wgpu::PollType::Wait {
                        submission_index: Some(index),
                        timeout: None,
                    })
                    .map_err(crate::GpuError::Poll)?;
            }
        }
        Ok(())
    }

    /// The newest frame's graph passes in the order they were recorded (passes culled because
    /// nothing needed them left out): the names its [`PassTiming`]s use. `None` before the
    /// first frame.
    pub fn graph_passes(&self) -> Option<Vec<String>> {
        self.graph_cache.pass_order()
    }

    /// Per-pass timings of every frame whose timestamps have arrived and were not yet returned
    /// (by `render`'s report or an earlier call), oldest first. Does not block. A frame that
    /// fails while its graph is recorded (a pass's bind group refused) drops the timings of the
    /// frames still in flight, so that no frame's timings carry its unwritten queries.
    pub fn drain_timings(&mut self) -> Vec<Vec<PassTiming>> {
        let _ = self.gpu.device().poll(wgpu::PollType::Poll);
        let mut frames = Vec::new();
        while let Some(r) = self
            .profiler
            .process_finished_frame(self.gpu.queue().get_timestamp_period())
        {
            frames.push(PassTiming::from_profiler(&r));
        }
        frames
    }

    /// The light culler of the configured path (built on the first frame; `Naive` before and on
    /// the naive paths), for tools that report on it: its lists' cells and bytes, whether it
    /// reads depth.
    pub fn culler(&self) -> &Culler {
        self.pass::<LightCullPass>()
            .map_or(&NO_CULLER, LightCullPass::culler)
    }

    /// The newest culling counters that have arrived, polling first.
    pub fn culling_counters(&mut self) -> Option<CullCounters> {
        self.pass_mut::<LightCullPass>()
            .and_then(LightCullPass::counters)
    }

    /// Waits for the GPU and returns the timings of the frames that finished (tools and tests).
    pub fn finish(&mut self) -> Option<Vec<PassTiming>> {
        let _ = self.gpu.wait_idle();
        let _ = self.culling_counters();
        let _ = self.particle_report();
        let _ = self.scene_draws();
        self.drain_timings().pop()
    }

    /// The scene's draws in the main view and how many the newest culled frame whose count
    /// has arrived drew, polling first; after [`Renderer::finish`], the last frame's.
    pub fn scene_draws(&mut self) -> Option<crate::frame_data::SceneDrawReport> {
        self.pass_mut::<crate::passes::scene_cull::SceneCullPass>()
            .and_then(crate::passes::scene_cull::SceneCullPass::report)
    }

    /// The last frame's shadow report (none without shadows), the casts it drew the newest
    /// count that has arrived (they are counted on the GPU); after [`Renderer::finish`], the
    /// last frame's own.
    pub fn shadow_report(&mut self) -> Option<crate::shadow::ShadowReport> {
        self.pass_mut::<crate::passes::shadow::ShadowPass>()
            .and_then(crate::passes::shadow::ShadowPass::report)
    }

    /// The newest particle counters that have arrived (none without particles); after
    /// [`Renderer::finish`], those of the last frame.
    pub fn particle_report(&mut self) -> Option<crate::frame_data::ParticleReport> {
        self.pass_mut::<crate::passes::particles::ParticleSimPass>()
            .and_then(crate::passes::particles::ParticleSimPass::report)
    }
}
