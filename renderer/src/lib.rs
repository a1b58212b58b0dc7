//! Data-oriented wgpu renderer: the GPU context, the frame graph, its passes, glTF scenes and
//! the engine-facing API.
//!
//! The renderer never creates a window and never holds hand-written shader source: every GPU
//! program comes from `shaders_gen`, which the shader DSL generates. An engine hands over a
//! device (or lets [`gpu::GpuContext`] create a headless one), a scene and a camera, and gets back
//! a frame and per-pass GPU timings.

#![warn(clippy::too_many_lines)]

pub mod culling;
pub mod decals;
pub mod frame;
pub mod frame_data;
pub mod gpu;
pub mod graph;
pub mod particles;
pub mod passes;
pub mod readback;
pub mod readback_ring;
pub mod scene;
pub mod shader;
pub mod shadow;
pub mod test_pattern;

pub use gpu::{AdapterReport, Capabilities, GpuContext, GpuError, GpuOptions};
