//! The shader DSL compiler as a plain library.
//!
//! `codegen` turns the Rust-syntax shader modules written with `shader-dsl` into WGSL and
//! SPIR-V for every variant, validates each with naga, and reflects bindings and host types.
//! It never depends on wgpu and never on proc-macro machinery beyond `syn`, so every stage can
//! be tested as an ordinary library.
//!
//! Stages (feature `compiler`, on by default):
//! [`front`] (Rust subset → typed [`ir`]) → [`variants`] (matrix, specialisation, pruning) →
//! [`back::wgsl`] (our printer + source map) → [`validate`] (naga) → [`back::spv`] →
//! [`reflect`] → [`emit`] (the tokens the macro returns). [`compile`] runs them all.
//! [`interp`] evaluates IR expressions on the host with the DSL's runtime semantics.
//!
//! Without `compiler`, only [`rt`] (the runtime reflection types generated code stores in
//! statics), [`web`] (a variant's WGSL for browsers, and its fit to WebGPU's limits) and the
//! hidden re-exports generated code needs are available.

// No panics on any input: errors are typed and point at the user's span. An invariant that truly
// holds is a documented `#[expect(clippy::expect_used, reason = ..)]`; tests may unwrap
// (clippy.toml). Indexing is not yet covered (clippy::indexing_slicing finds ~180 sites here).
#![warn(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

pub mod rt;
pub mod web;

#[cfg(feature = "compiler")]
pub mod back;
#[cfg(feature = "compiler")]
pub mod emit;
#[cfg(feature = "compiler")]
mod expand;
#[cfg(feature = "compiler")]
pub mod front;
#[cfg(feature = "compiler")]
pub mod interp;
#[cfg(feature = "compiler")]
pub mod ir;
#[cfg(feature = "compiler")]
pub mod layout;
#[cfg(feature = "compiler")]
mod link;
#[cfg(feature = "compiler")]
mod material;
#[cfg(feature = "compiler")]
mod pipeline;
#[cfg(feature = "compiler")]
pub mod reflect;
#[cfg(feature = "compiler")]
mod sources;
#[cfg(feature = "compiler")]
pub mod spirv_fix;
#[cfg(feature = "compiler")]
pub mod validate;
#[cfg(feature = "compiler")]
pub mod variants;

#[cfg(feature = "compiler")]
pub use expand::{expand, expand_library, expand_with_library};
#[cfg(feature = "compiler")]
pub use front::Library;
#[cfg(feature = "compiler")]
pub use link::{
    compile_library_linked, compile_linked, declarations_linked, library_declarations_linked,
};
#[cfg(feature = "compiler")]
pub use material::expand_material;
#[cfg(feature = "compiler")]
pub use pipeline::{
    Compiled, CompiledVariant, LinkedLibrary, NagaStructLayout, compile, compile_library,
    declarations,
};
#[cfg(feature = "compiler")]
pub use sources::{
    compile_library_with_libraries, compile_source, compile_source_all, compile_source_all_with,
    compile_with_libraries, libraries_of, library_modules, shader_modules,
};

/// Re-exports for generated code only. Not a public API.
#[doc(hidden)]
pub mod __private {
    pub use bytemuck;
    pub use glam;
}
