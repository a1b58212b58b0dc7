//! Back ends: our own WGSL printer (with a source map) and SPIR-V through naga.
//!
//! Like naga's `back/<lang>`, each has a small surface (`Options`, `write_*`). Back ends never
//! report user errors themselves: the front end and `validate` do.

pub mod spv;
pub mod wgsl;
