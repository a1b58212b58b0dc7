//! The pipelines built from one compiled program, shared by every copy of it
//! ([`super::store`]): compute pipelines by entry point, render pipelines by everything in
//! their descriptor except the module and layout, which must be the program's own (a
//! descriptor that names others is built without the memo).

use std::collections::HashMap;
use std::sync::{Mutex, PoisonError};

/// Pipelines built from one compiled program, shared by all its copies.
#[derive(Debug, Default)]
pub(crate) struct PipelineMemo {
    compute: Mutex<HashMap<&'static str, wgpu::ComputePipeline>>,
    render: Mutex<HashMap<String, wgpu::RenderPipeline>>,
    /// Pipelines built so far (each kept, so also how many are kept).
    built: std::sync::atomic::AtomicUsize,
}

impl PipelineMemo {
    /// The compute pipeline of `entry`, built by `build` the first time.
    pub(crate) fn compute(
        &self,
        entry: &'static str,
        build: impl FnOnce() -> wgpu::ComputePipeline,
    ) -> wgpu::ComputePipeline {
        let mut compute = self.compute.lock().unwrap_or_else(PoisonError::into_inner);
        compute
            .entry(entry)
            .or_insert_with(|| self.counted(build))
            .clone()
    }

    /// The render pipeline described by `key`, built by `build` the first time.
    pub(crate) fn render(
        &self,
        key: String,
        build: impl FnOnce() -> wgpu::RenderPipeline,
    ) -> wgpu::RenderPipeline {
        let mut render = self.render.lock().unwrap_or_else(PoisonError::into_inner);
        render
            .entry(key)
            .or_insert_with(|| self.counted(build))
            .clone()
    }

    /// Pipelines built so far.
    pub(crate) fn built(&self) -> usize {
        self.built.load(std::sync::atomic::Ordering::Relaxed)
    }

    fn counted<P>(&self, build: impl FnOnce() -> P) -> P {
        self.built
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        build()
    }
}

/// The render-state part of a descriptor whose module and layout are the program's own: the
/// key of its pipeline in the memo.
pub(crate) fn render_key(desc: &wgpu::RenderPipelineDescriptor<'_>) -> String {
    let fragment = desc
        .fragment
        .as_ref()
        .map(|f| (f.entry_point, &f.compilation_options, f.targets));
    format!(
        "{:?}",
        (
            desc.label,
            desc.vertex.entry_point,
            &desc.vertex.compilation_options,
            desc.vertex.buffers,
            desc.primitive,
            &desc.depth_stencil,
            desc.multisample,
            fragment,
            desc.multiview_mask,
        )
    )
}
