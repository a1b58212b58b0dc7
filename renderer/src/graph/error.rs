//! Mistakes in a frame graph, reported when it is compiled.

/// A frame graph that cannot run, and why.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum GraphError {
    #[error(
        "pass `{pass}` reads `{resource}`, which no pass writes first; add a pass that writes it \
         (transient resources start undefined) or import it"
    )]
    ReadBeforeWrite { pass: String, resource: String },

    #[error("pass `{pass}` writes `{resource}`, which was imported read-only")]
    WriteToReadOnlyImport { pass: String, resource: String },

    #[error(
        "pass `{pass}` writes `{resource}` through a stale handle (version {used}, latest \
         {latest}); use the handle returned by the previous write"
    )]
    StaleWrite {
        pass: String,
        resource: String,
        used: u32,
        latest: u32,
    },

    #[error("pass `{pass}` uses a handle or pass id that belongs to another frame graph")]
    ForeignHandle { pass: String },

    #[error("the passes {passes:?} depend on each other in a cycle")]
    Cycle { passes: Vec<String> },

    #[error("imported resource `{resource}` was given no GPU object before execution")]
    ImportNotBound { resource: String },

    #[error("imported resource `{resource}` was bound to a {given} but is a {expected}")]
    ImportKindMismatch {
        resource: String,
        expected: &'static str,
        given: &'static str,
    },

    #[error("pass `{pass}` could not bind its resources: {source}")]
    Bind {
        pass: String,
        source: shader_bind::BindError,
    },
}
