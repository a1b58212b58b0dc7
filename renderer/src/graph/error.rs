//! Mistakes in a frame graph, reported when it is compiled.

/// A frame graph that cannot run, and why.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum GraphError {
    /// A pass reads a transient resource version that no pass writes.
    #[error(
        "pass `{pass}` reads `{resource}`, which no pass writes first; add a pass that writes it \
         (transient resources start undefined) or import it"
    )]
    ReadBeforeWrite {
        /// The reading pass.
        pass: String,
        /// The resource read.
        resource: String,
    },

    /// A pass writes a resource imported with [`ImportAccess::ReadOnly`](super::ImportAccess::ReadOnly);
    /// import it [`ReadWrite`](super::ImportAccess::ReadWrite) or write a copy instead.
    #[error("pass `{pass}` writes `{resource}`, which was imported read-only")]
    WriteToReadOnlyImport {
        /// The writing pass.
        pass: String,
        /// The imported resource.
        resource: String,
    },

    /// A pass writes through a handle copied before a later write advanced the resource.
    #[error(
        "pass `{pass}` writes `{resource}` through a stale handle (version {used}, latest \
         {latest}); use the handle returned by the previous write"
    )]
    StaleWrite {
        /// The writing pass.
        pass: String,
        /// The resource written.
        resource: String,
        /// The version the stale handle names.
        used: u32,
        /// The resource's latest version, which the write must name.
        latest: u32,
    },

    /// A pass uses a [`Handle`](super::Handle) or [`PassId`](super::PassId) made by another
    /// [`RenderGraph`](super::RenderGraph) (for example one kept from the previous frame).
    #[error("pass `{pass}` uses a handle or pass id that belongs to another frame graph")]
    ForeignHandle {
        /// The pass that used it.
        pass: String,
    },

    /// Resource uses and [`PassBuilder::after`](super::PassBuilder::after) orderings form a
    /// cycle, so no pass order exists.
    #[error("the passes {passes:?} depend on each other in a cycle")]
    Cycle {
        /// The passes that could not be ordered: the cycle and the passes after it.
        passes: Vec<String>,
    },

    /// From `execute`: an import used by a kept pass got no `bind_texture`/`bind_buffer`
    /// call on the `CompiledGraph`.
    #[error("imported resource `{resource}` was given no GPU object before execution")]
    ImportNotBound {
        /// The unbound import.
        resource: String,
    },

    /// From `execute`: an import was bound to a buffer but declared a texture, or vice versa.
    #[error("imported resource `{resource}` was bound to a {given} but is a {expected}")]
    ImportKindMismatch {
        /// The import.
        resource: String,
        /// What it was declared as: `"texture"` or `"buffer"`.
        expected: &'static str,
        /// What was bound: `"texture"` or `"buffer"`.
        given: &'static str,
    },

    /// From `execute`: a pass's recording function could not build a bind group (kept by
    /// [`PassContext::bind`](super::PassContext::bind)); the pass stopped recording there.
    #[error("pass `{pass}` could not bind its resources: {source}")]
    Bind {
        /// The pass.
        pass: String,
        /// The first binding error it hit.
        source: shader_bind::BindError,
    },
}
