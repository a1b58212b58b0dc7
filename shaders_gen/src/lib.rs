//! The project's own GPU code: culling kernels and the forward, shadow, decal and particle
//! shaders, exposing every generated variant.
//!
//! The renderer takes all its shader code from here; it holds none of its own.
//! `bootstrap` is the only hand-written WGSL in the project, and the shader DSL (issue 3)
//! replaces it.

pub mod bootstrap;
