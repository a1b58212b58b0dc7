//! Data-oriented wgpu renderer: the GPU context, the frame graph, its passes, glTF scenes and
//! the engine-facing API.
//!
//! The renderer never creates a window and never holds hand-written shader source: every GPU
//! program comes from `shaders_gen`, which the shader DSL generates. An engine hands over a
//! device (or lets [`GpuContext`] create a headless one), a scene and a camera, and gets back
//! a frame and per-pass GPU timings.
//!
//! # The API
//! - [`gpu`]: the device ([`GpuContext`]), what it can do, and what the renderer needs of it.
//! - [`frame`]: the [`Renderer`](frame::Renderer), its configuration, views, cameras and
//!   reports, and [`RenderError`](frame::RenderError).
//! - [`scene`]: meshes, materials, textures, instances, lights and cameras, from glTF or built
//!   in code.
//! - [`materials`]: material programs written with `#[shader_dsl::material]`.
//! - [`decals`] and [`particles`]: projected decals and particle systems.
//! - [`extend`] and [`graph`]: passes an engine inserts into the frame, and the frame graph
//!   they declare their work on.
//! - [`shader`]: compiled shader variants and hot reload.
//! - [`readback`]: reading frames and buffers back to the CPU.
//!
//! # Features
//! - `gltf`, `png`, `json` (default): glTF scenes, PNG decal images, JSON decal sidecars.
//! - `demo`: the `demo` module, helpers for demos, tools and tests.
//! - `internals`: the internal modules, public and hidden from the docs, for this workspace's
//!   own tests, benchmarks and fuzzers; without it they are `pub(crate)`. Not part of the API.

#![warn(missing_docs)]
#![warn(clippy::too_many_lines)]
// No panics on any input: errors are typed. An invariant that truly holds is a documented
// `#[expect(clippy::expect_used, reason = ..)]`; tests may unwrap (clippy.toml). Indexing is not
// yet covered (clippy::indexing_slicing finds ~200 sites here).
#![warn(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

/// Declares internal modules: `pub(crate)`, or public and hidden from the docs with the
/// `internals` feature (for this workspace's tests, benchmarks and fuzzers).
macro_rules! internal_modules {
    ($($name:ident),* $(,)?) => {$(
        #[cfg(feature = "internals")]
        #[doc(hidden)]
        pub mod $name;
        #[cfg(not(feature = "internals"))]
        pub(crate) mod $name;
    )*};
}

/// Re-exports items of a public module that are internal: `pub(crate)`, or public and hidden
/// from the docs with the `internals` feature.
macro_rules! internal_use {
    ($($tree:tt)*) => {
        #[cfg(feature = "internals")]
        #[doc(hidden)]
        pub use $($tree)*;
        #[cfg(not(feature = "internals"))]
        pub(crate) use $($tree)*;
    };
}

pub mod decals;
#[cfg(feature = "demo")]
pub mod demo;
pub mod extend;
pub mod frame;
pub mod gpu;
pub mod graph;
pub mod materials;
pub mod particles;
pub mod readback;
pub mod scene;
pub mod shader;

internal_modules!(culling, frame_data, passes, readback_ring, shadow);

pub use gpu::{AdapterReport, Capabilities, GpuContext, GpuError, GpuOptions};
