//! Proc-macro front door of the shader DSL.
//!
//! This crate is only an adapter: it parses the macro input with `syn`, hands it to `codegen`,
//! and turns the result (or the error, at the user's span) back into tokens. Anything that can be
//! tested without a proc-macro lives in `codegen`. The language guide below is `GUIDE.md`; its
//! examples compile as doc tests of this crate.
//!
#![doc = include_str!("../GUIDE.md")]

use proc_macro::TokenStream;

/// Compiles an inline module of GPU code written in the DSL's Rust subset.
///
/// See the crate documentation for the language guide.
#[proc_macro_attribute]
pub fn shader(args: TokenStream, item: TokenStream) -> TokenStream {
    let args = proc_macro2::TokenStream::from(args);
    let item = proc_macro2::TokenStream::from(item);
    match codegen::expand(args.clone(), item.clone()) {
        Ok(tokens) => tokens.into(),
        Err(err) => {
            // The DSL's message first, then a stub of the module so the rest of the crate (and
            // the IDE) keeps resolving its host types and key types.
            let mut out = err.to_compile_error();
            if let Ok(module) = syn::parse2::<syn::ItemMod>(item) {
                let decls = codegen::declarations(args, &module);
                out.extend(codegen::emit::stub(&module, decls.as_ref()));
            }
            out.into()
        }
    }
}

/// Compiles a material: a module whose `fn surface(point: MaterialPoint) -> Surface` (with
/// `params = P`, `fn surface(point: MaterialPoint, params: P) -> Surface`) the renderer's
/// material frame shades on every path (forward with the naive, tiled or clustered lists,
/// blended, scalarized, and the deferred paths' G-buffer), with decals, shadows and MSAA.
///
/// It expands to a `#[shader]` module that uses the frame library (`frame = path`, by default
/// `shaders_gen::forward::material_frame`) and the libraries of `uses(..)`, has the frame's
/// axes, and gains the entry points `vs_forward`, `fs_forward` and `fs_gbuffer` and, with
/// `params`, the parameter records `PARAMS` at group 3, binding 0.
///
/// See "Materials" in the crate documentation.
#[proc_macro_attribute]
pub fn material(args: TokenStream, item: TokenStream) -> TokenStream {
    let args = proc_macro2::TokenStream::from(args);
    let item = proc_macro2::TokenStream::from(item);
    match codegen::expand_material(args, item.clone()) {
        Ok(tokens) => tokens.into(),
        Err(err) => {
            let mut out = err.to_compile_error();
            if let Ok(module) = syn::parse2::<syn::ItemMod>(item) {
                out.extend(codegen::emit::stub(&module, None));
            }
            out.into()
        }
    }
}

/// Declares a library: structs, constants, helper functions and statics that `#[shader]`
/// modules merge in with `uses(crate::path::to::library)`. The library is compiled and
/// validated on its own over its `axes(..)`; it may have no entry points.
///
/// See "Sharing code: libraries" in the crate documentation.
#[proc_macro_attribute]
pub fn library(args: TokenStream, item: TokenStream) -> TokenStream {
    codegen::expand_library(args.into(), item.into()).into()
}

/// One step of the `uses(..)` chain: generated code only, not an API.
#[doc(hidden)]
#[proc_macro]
pub fn __with_library(input: TokenStream) -> TokenStream {
    codegen::expand_with_library(input.into()).into()
}
