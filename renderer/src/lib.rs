//! Data-oriented wgpu renderer: the GPU context, the frame graph, its passes, glTF scenes and
//! the engine-facing API.
//!
//! The renderer never creates a window and never holds hand-written shader source: every GPU
//! program comes from `shaders_gen`, which the shader DSL generates. An engine hands over a
//! device (or lets [`gpu::GpuContext`] create a headless one), a scene and a camera, and gets back
//! a frame and per-pass GPU timings.

#![warn(clippy::too_many_lines)]
// No panics on any input: errors are typed. An invariant that truly holds is a documented
// `#[expect(clippy::expect_used, reason = ..)]`; tests may unwrap (clippy.toml). Indexing is not
// yet covered (clippy::indexing_slicing finds ~200 sites here).
#![warn(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

pub mod culling;
pub mod decals;
pub mod frame;
pub mod frame_data;
pub mod gpu;
pub mod graph;
pub mod materials;
pub mod particles;
pub mod passes;
pub mod readback;
pub mod readback_ring;
pub mod scene;
pub mod shader;
pub mod shadow;
pub mod test_pattern;

pub use gpu::{AdapterReport, Capabilities, GpuContext, GpuError, GpuOptions};
