//! The renderer's GPU timer: wgpu-profiler, one scope per graph pass, and what a frame that
//! fails while it is recorded leaves in it.

use super::Renderer;
use crate::frame_data::{DeviceError, RenderError};

impl Renderer {
    /// Records `compiled` into `encoder`. A frame that fails here is never submitted, but its
    /// passes' timer queries are in the profiler's open frame, where a later frame's timings
    /// would carry them unwritten: a new profiler drops them (and the timings still in flight).
    pub(super) fn execute_graph(
        &mut self,
        compiled: crate::graph::CompiledGraph,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<crate::graph::PoolStats, RenderError> {
        let device = self.gpu.device();
        match compiled.execute(device, encoder, &mut self.pool, &self.profiler) {
            Ok(pool) => Ok(pool),
            Err(error) => {
                self.profiler = Self::new_profiler(device)?;
                Err(error.into())
            }
        }
    }

    /// The renderer's GPU timer (wgpu-profiler, one scope per graph pass, no debug groups).
    pub(super) fn new_profiler(
        device: &wgpu::Device,
    ) -> Result<wgpu_profiler::GpuProfiler, RenderError> {
        let settings = wgpu_profiler::GpuProfilerSettings {
            enable_debug_groups: false,
            ..Default::default()
        };
        wgpu_profiler::GpuProfiler::new(device, settings)
            .map_err(|e| RenderError::Device(DeviceError::Profiler(e.to_string())))
    }
}
