//! Compiling a frame graph: dependency edges, pass culling, ordering, resource lifetimes and the
//! transient pool plan. Nothing here touches the GPU.

use std::collections::BTreeSet;
use std::sync::Arc;

use super::builder::RenderGraph;
use super::context::PoolObject;
use super::error::GraphError;
use super::nodes::{AccessKind, Lifetime, PassNode, ResourceDesc, ResourceNode, Usage};
use super::pool::{SlotPlan, plan_slots};

/// A graph ready to execute: its passes and resources, and the plan compiling made.
#[derive(Debug)]
pub struct CompiledGraph {
    pub(crate) passes: Vec<PassNode>,
    pub(crate) resources: Vec<ResourceNode>,
    pub(crate) plan: Arc<Plan>,
    /// GPU objects of imported resources, bound before execution.
    pub(crate) bound: Vec<Option<PoolObject>>,
}

/// What compiling decides: it depends only on the graph's shape (its resources and what each
/// pass reads and writes), never on what the passes record.
#[derive(Debug, PartialEq)]
pub(crate) struct Plan {
    /// Indices of the passes to run, in order.
    pub order: Vec<usize>,
    /// Per resource: its lifetime over `order`, `None` if no kept pass uses it.
    pub lifetimes: Vec<Option<Lifetime>>,
    /// Physical slots for transients, and each transient's slot.
    pub slots: Vec<SlotPlan>,
    pub slot_of: Vec<Option<usize>>,
}

impl RenderGraph {
    /// Checks, culls, orders and plans the graph.
    pub fn compile(self) -> Result<CompiledGraph, GraphError> {
        if let Some(error) = self.errors.into_iter().next() {
            return Err(error);
        }
        let (data_edges, order_edges) = edges(&self.passes, &self.resources)?;
        let all_edges: Vec<(usize, usize)> =
            data_edges.iter().chain(&order_edges).copied().collect();
        let sorted = topological_order(self.passes.len(), &all_edges).map_err(|stuck| {
            GraphError::Cycle {
                passes: stuck.iter().map(|&p| self.passes[p].name.clone()).collect(),
            }
        })?;
        let kept = kept_passes(&self.passes, &self.resources, &data_edges);
        let order: Vec<usize> = sorted.into_iter().filter(|p| kept.contains(p)).collect();
        let (lifetimes, usages) = lifetimes_and_usage(&self.passes, &self.resources, &order);
        let (slots, slot_of) = plan_slots(&self.resources, &lifetimes, &usages);
        Ok(CompiledGraph {
            passes: self.passes,
            resources: self.resources,
            plan: Arc::new(Plan {
                order,
                lifetimes,
                slots,
                slot_of,
            }),
            bound: Vec::new(),
        })
    }
}

impl CompiledGraph {
    /// Names of the passes that will run, in order.
    pub fn pass_order(&self) -> Vec<&str> {
        self.plan
            .order
            .iter()
            .map(|&p| self.passes[p].name.as_str())
            .collect()
    }

    /// Names of the passes culled because nothing needs their results.
    pub fn culled_passes(&self) -> Vec<&str> {
        (0..self.passes.len())
            .filter(|p| !self.plan.order.contains(p))
            .map(|p| self.passes[p].name.as_str())
            .collect()
    }

    /// The lifetime of the resource called `name`.
    pub fn lifetime(&self, name: &str) -> Option<Lifetime> {
        let index = self.resources.iter().position(|r| r.name == name)?;
        self.plan.lifetimes[index]
    }

    /// The pool slot of the transient called `name` (equal slots share one GPU object).
    pub fn slot(&self, name: &str) -> Option<usize> {
        let index = self.resources.iter().position(|r| r.name == name)?;
        self.plan.slot_of[index]
    }

    /// Number of physical transient objects this frame needs.
    pub fn slot_count(&self) -> usize {
        self.plan.slots.len()
    }
}

/// Data edges (read-after-write, write-after-write, explicit `after`) decide culling; order
/// edges (write-after-read) only constrain the order of passes that are kept anyway.
type Edges = Vec<(usize, usize)>;

fn edges(passes: &[PassNode], resources: &[ResourceNode]) -> Result<(Edges, Edges), GraphError> {
    // writer[resource][version] = pass that produced it.
    let mut writer: Vec<Vec<Option<usize>>> = resources
        .iter()
        .map(|r| vec![None; r.latest as usize + 1])
        .collect();
    for (p, pass) in passes.iter().enumerate() {
        for w in &pass.writes {
            writer[w.resource][w.version as usize] = Some(p);
        }
    }
    let mut data = BTreeSet::new();
    let mut order = BTreeSet::new();
    for (p, pass) in passes.iter().enumerate() {
        for r in &pass.reads {
            match writer[r.resource][r.version as usize] {
                Some(w) if w != p => {
                    data.insert((w, p));
                }
                Some(_) => {}
                None if resources[r.resource].import.is_some() => {} // written outside
                None => {
                    return Err(GraphError::ReadBeforeWrite {
                        pass: pass.name.clone(),
                        resource: resources[r.resource].name.clone(),
                    });
                }
            }
        }
        for w in &pass.writes {
            let previous = w.version - 1;
            if let Some(prev_writer) = writer[w.resource][previous as usize].filter(|&q| q != p) {
                data.insert((prev_writer, p));
            }
            // Everyone reading the previous version must read it before it is overwritten.
            for (q, other) in passes.iter().enumerate() {
                let reads_previous = other
                    .reads
                    .iter()
                    .any(|r| r.resource == w.resource && r.version == previous);
                if q != p && reads_previous {
                    order.insert((q, p));
                }
            }
        }
        for &before in &pass.after {
            data.insert((before, p));
        }
    }
    Ok((data.into_iter().collect(), order.into_iter().collect()))
}

/// Kahn's algorithm, taking the earliest-declared ready pass first so the order is stable.
/// On a cycle, returns the passes that could not be ordered.
fn topological_order(count: usize, edges: &[(usize, usize)]) -> Result<Vec<usize>, Vec<usize>> {
    let mut indegree = vec![0usize; count];
    for &(_, to) in edges {
        indegree[to] += 1;
    }
    let mut ready: BTreeSet<usize> = (0..count).filter(|&p| indegree[p] == 0).collect();
    let mut order = Vec::with_capacity(count);
    while let Some(p) = ready.pop_first() {
        order.push(p);
        for &(from, to) in edges {
            if from == p {
                indegree[to] -= 1;
                if indegree[to] == 0 {
                    ready.insert(to);
                }
            }
        }
    }
    if order.len() == count {
        Ok(order)
    } else {
        Err((0..count).filter(|p| !order.contains(p)).collect())
    }
}

/// Passes with side effects or writes to imported resources, and everything they need.
fn kept_passes(
    passes: &[PassNode],
    resources: &[ResourceNode],
    data_edges: &[(usize, usize)],
) -> BTreeSet<usize> {
    let mut stack: Vec<usize> = passes
        .iter()
        .enumerate()
        .filter(|(_, pass)| {
            pass.side_effects
                || pass
                    .writes
                    .iter()
                    .any(|w| resources[w.resource].import.is_some())
        })
        .map(|(p, _)| p)
        .collect();
    let mut kept = BTreeSet::new();
    while let Some(p) = stack.pop() {
        if kept.insert(p) {
            stack.extend(
                data_edges
                    .iter()
                    .filter(|(_, to)| *to == p)
                    .map(|(from, _)| *from),
            );
        }
    }
    kept
}

fn lifetimes_and_usage(
    passes: &[PassNode],
    resources: &[ResourceNode],
    order: &[usize],
) -> (Vec<Option<Lifetime>>, Vec<Usage>) {
    let mut lifetimes: Vec<Option<Lifetime>> = vec![None; resources.len()];
    let mut usages: Vec<Usage> = resources
        .iter()
        .map(|r| match r.desc {
            // wgpu creates multisampled textures only as render attachments, whatever their use.
            ResourceDesc::Texture(t) if t.sample_count > 1 => {
                Usage::Texture(wgpu::TextureUsages::RENDER_ATTACHMENT)
            }
            ResourceDesc::Texture(_) => Usage::Texture(wgpu::TextureUsages::empty()),
            // COPY_SRC: tools read back what a kernel bound (the tests' host replay).
            ResourceDesc::Buffer(_) => Usage::Buffer(wgpu::BufferUsages::COPY_SRC),
        })
        .collect();
    for (position, &p) in order.iter().enumerate() {
        for u in passes[p].reads.iter().chain(&passes[p].writes) {
            let lifetime = lifetimes[u.resource].get_or_insert(Lifetime {
                first: position,
                last: position,
            });
            lifetime.last = position;
            match (&mut usages[u.resource], u.kind) {
                (Usage::Texture(flags), AccessKind::Texture(a)) => *flags |= a.usage(),
                (Usage::Buffer(flags), AccessKind::Buffer(a)) => *flags |= a.usage(),
                _ => unreachable!("handles are typed: a texture handle only has texture accesses"),
            }
        }
    }
    (lifetimes, usages)
}
