//! Building a frame graph: resources, passes and what each pass reads and writes.

use std::sync::atomic::{AtomicU64, Ordering};

use super::context::PassContext;
use super::error::GraphError;
use super::nodes::{AccessKind, PassNode, ResourceDesc, ResourceNode, Use};
use super::resource::{
    Buffer, BufferAccess, BufferDesc, Handle, ImportAccess, Texture, TextureAccess, TextureDesc,
};

/// Identifies a pass of one graph.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct PassId {
    pub(crate) graph: u64,
    pub(crate) index: usize,
}

/// A frame graph being built. Compile it with [`RenderGraph::compile`].
#[derive(Debug)]
pub struct RenderGraph {
    pub(crate) id: u64,
    pub(crate) resources: Vec<ResourceNode>,
    pub(crate) passes: Vec<PassNode>,
    /// Mistakes found while building, reported by `compile`.
    pub(crate) errors: Vec<GraphError>,
}

impl Default for RenderGraph {
    fn default() -> Self {
        Self::new()
    }
}

impl RenderGraph {
    /// An empty graph with an id of its own, so handles from other graphs are rejected.
    pub fn new() -> Self {
        static NEXT_ID: AtomicU64 = AtomicU64::new(1);
        Self {
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
            resources: Vec::new(),
            passes: Vec::new(),
            errors: Vec::new(),
        }
    }

    fn add_resource<T>(
        &mut self,
        name: &str,
        desc: ResourceDesc,
        import: Option<ImportAccess>,
    ) -> Handle<T> {
        self.resources.push(ResourceNode {
            name: name.to_owned(),
            desc,
            import,
            // An import arrives with content: version 1, written outside the graph.
            latest: u32::from(import.is_some()),
        });
        let mut handle = Handle::new(self.id, self.resources.len() - 1);
        handle.version = self.resources[handle.index].latest;
        handle
    }

    /// A texture the graph creates for this frame from its pool.
    pub fn create_texture(&mut self, name: &str, desc: TextureDesc) -> Handle<Texture> {
        self.add_resource(name, ResourceDesc::Texture(desc), None)
    }

    /// A buffer the graph creates for this frame from its pool.
    pub fn create_buffer(&mut self, name: &str, desc: BufferDesc) -> Handle<Buffer> {
        self.add_resource(name, ResourceDesc::Buffer(desc), None)
    }

    /// A persistent texture owned outside the graph (bind its object before executing).
    pub fn import_texture(
        &mut self,
        name: &str,
        desc: TextureDesc,
        access: ImportAccess,
    ) -> Handle<Texture> {
        self.add_resource(name, ResourceDesc::Texture(desc), Some(access))
    }

    /// A persistent buffer owned outside the graph (bind its object before executing).
    pub fn import_buffer(
        &mut self,
        name: &str,
        desc: BufferDesc,
        access: ImportAccess,
    ) -> Handle<Buffer> {
        self.add_resource(name, ResourceDesc::Buffer(desc), Some(access))
    }

    /// Starts a pass; finish it with [`PassBuilder::execute`] or [`PassBuilder::finish`].
    pub fn add_pass(&mut self, name: &str) -> PassBuilder<'_> {
        self.passes.push(PassNode {
            name: name.to_owned(),
            reads: Vec::new(),
            writes: Vec::new(),
            after: Vec::new(),
            side_effects: false,
            execute: None,
        });
        let index = self.passes.len() - 1;
        PassBuilder { graph: self, index }
    }

    /// The name of a resource, for messages and dumps; `None` for a handle of another graph.
    pub fn resource_name<T>(&self, handle: Handle<T>) -> Option<&str> {
        if handle.graph != self.id {
            return None;
        }
        self.resources.get(handle.index).map(|r| r.name.as_str())
    }
}

/// Declares what one pass reads and writes.
#[derive(Debug)]
pub struct PassBuilder<'g> {
    graph: &'g mut RenderGraph,
    index: usize,
}

impl PassBuilder<'_> {
    fn pass_name(&self) -> String {
        self.graph.passes[self.index].name.clone()
    }

    fn check_graph(&mut self, graph: u64) -> bool {
        if graph == self.graph.id {
            return true;
        }
        let pass = self.pass_name();
        self.graph.errors.push(GraphError::ForeignHandle { pass });
        false
    }

    fn read(&mut self, graph: u64, resource: usize, version: u32, kind: AccessKind) {
        if self.check_graph(graph) {
            self.graph.passes[self.index].reads.push(Use {
                resource,
                version,
                kind,
            });
        }
    }

    /// Advances the resource to a new version written by this pass.
    fn write(&mut self, graph: u64, resource: usize, version: &mut u32, kind: AccessKind) {
        if !self.check_graph(graph) {
            return;
        }
        let node = &self.graph.resources[resource];
        let pass = self.pass_name();
        if node.import == Some(ImportAccess::ReadOnly) {
            let resource = node.name.clone();
            self.graph
                .errors
                .push(GraphError::WriteToReadOnlyImport { pass, resource });
            return;
        }
        if *version != node.latest {
            self.graph.errors.push(GraphError::StaleWrite {
                pass,
                resource: node.name.clone(),
                used: *version,
                latest: node.latest,
            });
            return;
        }
        *version += 1;
        self.graph.resources[resource].latest = *version;
        self.graph.passes[self.index].writes.push(Use {
            resource,
            version: *version,
            kind,
        });
    }

    /// This pass reads `texture` (the version the handle names).
    pub fn read_texture(&mut self, texture: Handle<Texture>, access: TextureAccess) -> &mut Self {
        self.read(
            texture.graph,
            texture.index,
            texture.version,
            AccessKind::Texture(access),
        );
        self
    }

    /// This pass writes `texture`; the handle now names the new version.
    pub fn write_texture(
        &mut self,
        texture: &mut Handle<Texture>,
        access: TextureAccess,
    ) -> &mut Self {
        let (graph, index) = (texture.graph, texture.index);
        self.write(
            graph,
            index,
            &mut texture.version,
            AccessKind::Texture(access),
        );
        self
    }

    /// This pass reads `buffer` (the version the handle names).
    pub fn read_buffer(&mut self, buffer: Handle<Buffer>, access: BufferAccess) -> &mut Self {
        self.read(
            buffer.graph,
            buffer.index,
            buffer.version,
            AccessKind::Buffer(access),
        );
        self
    }

    /// This pass writes `buffer`; the handle now names the new version.
    pub fn write_buffer(&mut self, buffer: &mut Handle<Buffer>, access: BufferAccess) -> &mut Self {
        let (graph, index) = (buffer.graph, buffer.index);
        self.write(
            graph,
            index,
            &mut buffer.version,
            AccessKind::Buffer(access),
        );
        self
    }

    /// Orders this pass after `pass` even without a resource between them.
    pub fn after(&mut self, pass: PassId) -> &mut Self {
        if self.check_graph(pass.graph) {
            self.graph.passes[self.index].after.push(pass.index);
        }
        self
    }

    /// Keeps this pass even if nothing reads what it writes (readbacks, queries, uploads).
    pub fn side_effects(&mut self) -> &mut Self {
        self.graph.passes[self.index].side_effects = true;
        self
    }

    /// Sets the recording function and finishes the pass.
    pub fn execute(&mut self, record: impl FnOnce(&mut PassContext<'_>) + 'static) -> PassId {
        self.graph.passes[self.index].execute = Some(Box::new(record));
        self.id()
    }

    /// Finishes a pass that records nothing (useful for ordering and in tests).
    pub fn finish(&mut self) -> PassId {
        self.id()
    }

    fn id(&self) -> PassId {
        PassId {
            graph: self.graph.id,
            index: self.index,
        }
    }
}
