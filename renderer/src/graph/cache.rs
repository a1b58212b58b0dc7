//! Compiling a frame graph once: a plan (order, culling, lifetimes, pool slots) depends only on
//! the graph's shape, so a frame whose graph has the shape of the last one compiled reuses its
//! plan and only records. The shape changes with the configuration, the pass list, a resource's
//! size or format, or what a pass reads and writes (a frame with particles or a capture, say);
//! the cache then compiles again. It also keeps what DOT needs, so the graph is drawn on
//! request, not every frame.

use std::sync::Arc;

use super::builder::RenderGraph;
use super::compile::{CompiledGraph, Plan};
use super::dot;
use super::error::GraphError;
use super::nodes::{PassNode, ResourceNode};

/// The shape and plan of the last graph compiled.
#[derive(Debug, Default)]
pub struct GraphCache {
    /// The graph's resources and passes (without their recording functions).
    resources: Vec<ResourceNode>,
    passes: Vec<PassNode>,
    plan: Option<Arc<Plan>>,
    /// Graphs compiled, and graphs that reused a plan.
    compiled: u64,
    reused: u64,
}

impl GraphCache {
    /// An empty cache: the first graph compiled through it is compiled in full.
    pub fn new() -> Self {
        Self::default()
    }

    /// Graphs compiled so far, and graphs that reused the plan of the one before.
    pub fn counts(&self) -> (u64, u64) {
        (self.compiled, self.reused)
    }

    /// The last graph in Graphviz DOT ([`CompiledGraph::to_dot`]), if one was compiled.
    pub fn to_dot(&self) -> Option<String> {
        let plan = self.plan.as_ref()?;
        Some(dot::to_dot(&self.passes, &self.resources, plan))
    }

    /// The last graph's passes in the order they were recorded (culled ones left out), if one
    /// was compiled.
    pub fn pass_order(&self) -> Option<Vec<String>> {
        let plan = self.plan.as_ref()?;
        Some(
            plan.order
                .iter()
                .map(|&p| self.passes[p].name.clone())
                .collect(),
        )
    }

    /// Whether `graph` has the shape the plan was made for.
    fn fits(&self, graph: &RenderGraph) -> bool {
        self.plan.is_some()
            && self.resources == graph.resources
            && self.passes.len() == graph.passes.len()
            && self
                .passes
                .iter()
                .zip(&graph.passes)
                .all(|(a, b)| a.same_shape(b))
    }
}

impl RenderGraph {
    /// [`RenderGraph::compile`], reusing `cache`'s plan when this graph has the shape of the
    /// one it was made for.
    pub fn compile_cached(self, cache: &mut GraphCache) -> Result<CompiledGraph, GraphError> {
        if let Some(plan) = cache.plan.as_ref().filter(|_| cache.fits(&self)) {
            if let Some(error) = self.errors.into_iter().next() {
                return Err(error);
            }
            cache.reused += 1;
            return Ok(CompiledGraph {
                passes: self.passes,
                resources: self.resources,
                plan: Arc::clone(plan),
                bound: Vec::new(),
            });
        }
        let compiled = self.compile()?;
        cache.resources.clone_from(&compiled.resources);
        cache.passes = compiled.passes.iter().map(PassNode::shape).collect();
        cache.plan = Some(Arc::clone(&compiled.plan));
        cache.compiled += 1;
        Ok(compiled)
    }
}
