//! The bodies of the coverage-guided fuzz targets, as a library: the libFuzzer binaries in
//! `fuzz_targets/` call them (`cargo xtask fuzz TARGET --minutes M`), and `tests/regressions.rs`
//! replays every committed input and seed through them as ordinary tests.
//!
//! Each body panics only when the code under test breaks its contract (a panic of its own, or
//! an oracle's assertion); bad input must come back as a typed error.

pub mod alloc_limit;
pub mod dsl_codegen;
pub mod frame_graph;
pub mod gltf_load;
pub mod gltf_mutate;
pub mod gltf_seeds;

/// A target's body: one input, a panic on a broken contract.
pub type Body = fn(&[u8]);

/// The fuzz targets by name, with their bodies.
pub const TARGETS: &[(&str, Body)] = &[
    ("gltf_load", gltf_load::run),
    ("dsl_codegen", dsl_codegen::run),
    ("frame_graph", frame_graph::run),
];
