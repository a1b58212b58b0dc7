//! Recording a compiled graph: pool objects for transients, imports bound by the caller, one
//! debug group and one GPU timestamp scope per pass.

use std::sync::Arc;

use super::compile::CompiledGraph;
use super::context::{PassContext, PoolObject};
use super::error::GraphError;
use super::nodes::ResourceDesc;
use super::pool::{PoolStats, TransientPool};
use super::resource::{Buffer, Handle, Texture};

/// GPU time of one pass, once the timestamps are back.
#[derive(Debug, Clone, PartialEq)]
pub struct PassTiming {
    /// The profiler scope's label: the pass name, or a nested scope's own label.
    pub pass: String,
    /// GPU time between the scope's timestamps, in milliseconds.
    pub gpu_ms: f64,
}

impl PassTiming {
    /// Flattens wgpu-profiler's results for one frame into per-pass timings (nested scopes are
    /// listed after their parent). Scopes without a time (no timestamp support) are skipped.
    pub fn from_profiler(results: &[wgpu_profiler::GpuTimerQueryResult]) -> Vec<Self> {
        let mut out = Vec::new();
        for r in results {
            if let Some(t) = &r.time {
                out.push(Self {
                    pass: r.label.clone(),
                    gpu_ms: (t.end - t.start) * 1e3,
                });
            }
            out.extend(Self::from_profiler(&r.nested_queries));
        }
        out
    }
}

impl CompiledGraph {
    /// Binds an imported texture's GPU object.
    pub fn bind_texture(&mut self, handle: Handle<Texture>, texture: &wgpu::Texture) -> &mut Self {
        self.imports_mut()[handle.index] = Some(PoolObject::Texture(texture.clone()));
        self
    }

    /// Binds an imported buffer's GPU object.
    pub fn bind_buffer(&mut self, handle: Handle<Buffer>, buffer: &wgpu::Buffer) -> &mut Self {
        self.imports_mut()[handle.index] = Some(PoolObject::Buffer(buffer.clone()));
        self
    }

    fn imports_mut(&mut self) -> &mut Vec<Option<PoolObject>> {
        let n = self.resources.len();
        let imports = &mut self.bound;
        imports.resize(n, None);
        imports
    }

    /// Records every kept pass into `encoder`, in order, each inside a profiler scope.
    pub fn execute(
        mut self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        pool: &mut TransientPool,
        profiler: &wgpu_profiler::GpuProfiler,
    ) -> Result<PoolStats, GraphError> {
        let n = self.resources.len();
        self.bound.resize(n, None);
        let mut objects = std::mem::take(&mut self.bound);
        for (i, r) in self.resources.iter().enumerate() {
            if r.import.is_none() || self.plan.lifetimes[i].is_none() {
                continue;
            }
            let expected = kind_name(&r.desc);
            match &objects[i] {
                None => {
                    return Err(GraphError::ImportNotBound {
                        resource: r.name.clone(),
                    });
                }
                Some(o) if object_kind(o) != expected => {
                    return Err(GraphError::ImportKindMismatch {
                        resource: r.name.clone(),
                        expected,
                        given: object_kind(o),
                    });
                }
                Some(_) => {}
            }
        }
        let (physical, stats) = pool.acquire(device, &self.plan.slots);
        for (i, slot) in self.plan.slot_of.iter().enumerate() {
            if let Some(slot) = slot {
                objects[i] = Some(physical[*slot].clone());
            }
        }
        let plan = Arc::clone(&self.plan);
        for &p in &plan.order {
            let pass = &mut self.passes[p];
            let mut scope = profiler.scope(pass.name.clone(), &mut *encoder);
            if let Some(record) = pass.execute.take() {
                let mut ctx = PassContext::new(&mut scope, device, profiler, &objects);
                record(&mut ctx);
                if let Some(source) = ctx.bind_error.take() {
                    return Err(GraphError::Bind {
                        pass: pass.name.clone(),
                        source,
                    });
                }
            }
        }
        Ok(stats)
    }
}

fn kind_name(desc: &ResourceDesc) -> &'static str {
    match desc {
        ResourceDesc::Texture(_) => "texture",
        ResourceDesc::Buffer(_) => "buffer",
    }
}

fn object_kind(o: &PoolObject) -> &'static str {
    match o {
        PoolObject::Texture(_) => "texture",
        PoolObject::Buffer(_) => "buffer",
    }
}
