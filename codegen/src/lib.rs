//! The shader DSL compiler as a plain library.
//!
//! `codegen` turns the Rust-syntax shader modules written with `shader-dsl` into WGSL and
//! SPIR-V for every variant, validates each with naga, and reflects bindings and host types.
//! It never depends on wgpu and never on proc-macro machinery beyond `syn`, so every stage can
//! be tested as an ordinary library.
