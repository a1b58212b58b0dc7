//! A lean frame graph: passes declare the resources they read and write, the graph orders them,
//! culls what nothing needs, plans transient resources from a pool, and records them with
//! debug labels and per-pass GPU timestamps.
//!
//! Lifecycle: [`RenderGraph`] (passes are added) → [`RenderGraph::compile`] →
//! `CompiledGraph` (order, lifetimes, pool plan; no GPU needed) →
//! `CompiledGraph::execute` (records the passes on a device). A renderer compiles through a
//! `GraphCache` (`RenderGraph::compile_cached`): a frame whose graph has the last one's
//! shape reuses its plan, and DOT is drawn from the cache on request.
//!
//! Handles are versioned: writing a resource takes `&mut Handle` and advances it, so a read
//! always names the exact write it depends on. Mistakes are [`GraphError`]s at compile time,
//! never wgpu validation errors later.
//!
//! Files are layered, each using only those below it: `resource`, `error`, `encoder` (how compute
//! and render passes begin, timed) → `context` (what a recording function gets) → `nodes` (the
//! shared plain data) → `builder`, `pool` → `compile` → `execute`, `dot` → `cache`.
//! `cargo xtask check-invariants` rejects any import circle between them.

mod builder;
mod cache;
mod compile;
mod context;
mod dot;
mod encoder;
mod error;
mod execute;
mod nodes;
mod pool;
mod resource;

pub use builder::{PassBuilder, PassId, RenderGraph};
internal_use!(cache::GraphCache);
internal_use!(compile::CompiledGraph);
pub use context::PassContext;
pub use encoder::{PassEncoder, TimedPass};
pub use error::GraphError;
pub use execute::PassTiming;
pub use nodes::Lifetime;
internal_use!(pool::{PoolStats, TransientPool});
pub use resource::{
    Buffer, BufferAccess, BufferDesc, Handle, ImportAccess, Texture, TextureAccess, TextureDesc,
};

#[cfg(test)]
mod tests;
