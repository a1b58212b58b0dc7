//! Recording a compiled graph: pool objects for transients, imports bound by the caller, one
//! debug group and one GPU timestamp scope per pass.

use std::sync::Arc;

use super::compile::CompiledGraph;
use super::context::{PassContext, PoolObject};
use super::encoder::PassEncoder;
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
    /// listed after their parent).
    ///
    /// A scope without a time of its own whose compute and render passes carry timestamps (a
    /// device that times only whole passes, as WebGPU does: see `graph::encoder`) is timed as
    /// the sum of those passes, and they are not listed again. Scopes with no time at all (no
    /// timestamp support) are skipped.
    pub fn from_profiler(results: &[wgpu_profiler::GpuTimerQueryResult]) -> Vec<Self> {
        let mut out = Vec::new();
        for r in results {
            match &r.time {
                Some(t) => {
                    out.push(Self {
                        pass: r.label.clone(),
                        gpu_ms: (t.end - t.start) * 1e3,
                    });
                    out.extend(Self::from_profiler(&r.nested_queries));
                }
                None => match summed_seconds(&r.nested_queries) {
                    Some(seconds) => out.push(Self {
                        pass: r.label.clone(),
                        gpu_ms: seconds * 1e3,
                    }),
                    None => out.extend(Self::from_profiler(&r.nested_queries)),
                },
            }
        }
        out
    }
}

/// The summed time of the timed scopes among `results` (for an untimed one, of its own nested
/// scopes), or `None` when none has a time.
fn summed_seconds(results: &[wgpu_profiler::GpuTimerQueryResult]) -> Option<f64> {
    results
        .iter()
        .filter_map(|r| match &r.time {
            Some(t) => Some(t.end - t.start),
            None => summed_seconds(&r.nested_queries),
        })
        .reduce(|a, b| a + b)
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
            let scope = profiler.begin_query(pass.name.clone(), &mut *encoder);
            let mut bind_error = None;
            if let Some(record) = pass.execute.take() {
                let pass_encoder =
                    PassEncoder::for_graph_pass(&mut *encoder, device, profiler, &scope);
                let mut ctx = PassContext::new(pass_encoder, device, &objects);
                record(&mut ctx);
                bind_error = ctx.bind_error.take();
            }
            // The scope is closed on every path: the profiler refuses to end a frame with one
            // left open.
            profiler.end_query(&mut *encoder, scope);
            if let Some(source) = bind_error {
                return Err(GraphError::Bind {
                    pass: pass.name.clone(),
                    source,
                });
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
