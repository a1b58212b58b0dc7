//! The graph's plain data, shared by building, compiling, pool planning and execution: resource
//! and pass nodes, the uses that link them, resource lifetimes and accumulated usage. It sits
//! below all of them, so none of them needs another's types.

use super::context::PassContext;
use super::resource::{BufferAccess, BufferDesc, ImportAccess, TextureAccess, TextureDesc};

pub(crate) type ExecuteFn = Box<dyn FnOnce(&mut PassContext<'_>) + 'static>;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum ResourceDesc {
    Texture(TextureDesc),
    Buffer(BufferDesc),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum AccessKind {
    Texture(TextureAccess),
    Buffer(BufferAccess),
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ResourceNode {
    pub name: String,
    pub desc: ResourceDesc,
    /// `None` for transients; the import's access otherwise.
    pub import: Option<ImportAccess>,
    /// The latest version (0 = nothing written yet).
    pub latest: u32,
}

/// One use of a resource version by a pass. For a write, `version` is the version it produces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Use {
    pub resource: usize,
    pub version: u32,
    pub kind: AccessKind,
}

pub(crate) struct PassNode {
    pub name: String,
    pub reads: Vec<Use>,
    pub writes: Vec<Use>,
    pub after: Vec<usize>,
    pub side_effects: bool,
    pub execute: Option<ExecuteFn>,
}

impl PassNode {
    /// The pass without its recording function: what the graph's plan depends on.
    pub fn shape(&self) -> Self {
        Self {
            name: self.name.clone(),
            reads: self.reads.clone(),
            writes: self.writes.clone(),
            after: self.after.clone(),
            side_effects: self.side_effects,
            execute: None,
        }
    }

    /// Whether `other` reads, writes and orders like this pass, under the same name.
    pub fn same_shape(&self, other: &Self) -> bool {
        self.name == other.name
            && self.reads == other.reads
            && self.writes == other.writes
            && self.after == other.after
            && self.side_effects == other.side_effects
    }
}

impl std::fmt::Debug for PassNode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PassNode")
            .field("name", &self.name)
            .field("reads", &self.reads)
            .field("writes", &self.writes)
            .field("after", &self.after)
            .field("side_effects", &self.side_effects)
            .finish_non_exhaustive()
    }
}

/// The first and last position (in execution order) at which a resource is used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Lifetime {
    /// Position of the first pass using it, as an index into
    /// `CompiledGraph::pass_order`.
    pub first: usize,
    /// Position of the last pass using it (inclusive).
    pub last: usize,
}

/// Accumulated usage flags of a resource.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum Usage {
    Texture(wgpu::TextureUsages),
    Buffer(wgpu::BufferUsages),
}
