//! Front end: the Rust subset (a syn `ItemMod` plus the macro arguments) to typed IR.
//!
//! Name resolution and type checking happen here, and every error carries the span of the
//! Rust construct at fault with a message that says what is allowed instead. The front end
//! must not print WGSL or evaluate axes (that is `variants`), and must not call naga.

mod args;
mod attrs;
mod build;
mod calls;
mod checks;
mod ctx;
mod expr;
mod fncall;
mod items;
mod lib_graph;
mod libs;
mod ops;
mod resources;
mod signature;
mod statics;
mod stmt;
mod types;

pub(crate) use checks::mentions_axis;

pub use ctx::Mode;
pub(crate) use lib_graph::{Root, by_full_path, order, reached_by};
pub use libs::Library;
pub(crate) use libs::path_text;

use ctx::ModCtx;

use crate::ir::Module;
use proc_macro2::TokenStream;
use syn::{Error, Result};

/// Lowers a shader module: the attribute arguments and the `mod` item.
pub fn lower(args: TokenStream, item: &syn::ItemMod) -> Result<Module> {
    lower_with(args, item, &[], Mode::Shader)
}

/// Lowers only the declarations the host side sees (see [`Mode::Declarations`]).
pub fn lower_declarations(args: TokenStream, item: &syn::ItemMod) -> Result<Module> {
    lower_with(args, item, &[], Mode::Declarations)
}

/// The libraries a module's attribute arguments name in `uses(..)`, in order.
pub fn uses_of(args: TokenStream) -> Result<Vec<syn::Path>> {
    Ok(args::parse_args(args)?.uses)
}

/// Lowers a module, or a library (`Mode::Library`), with the libraries its `uses(..)` reaches
/// merged in: `libs`, ordered by [`order`] (dependencies first, each once).
pub fn lower_with(
    args: TokenStream,
    item: &syn::ItemMod,
    libs: &[Library],
    mode: Mode,
) -> Result<Module> {
    let args = args::parse_args(args)?;
    let mut m = ModCtx::new(item);
    m.module.library = mode == Mode::Library;
    let Some((_, content)) = &item.content else {
        return Err(Error::new(
            item.ident.span(),
            "a shader module must be inline: `mod name { .. }`",
        ));
    };
    if mode == Mode::Library {
        libs::check_library_args(&args)?;
    }
    for p in &args.uses {
        let last = p.segments.last().map(|s| s.ident.to_string());
        let found = libs
            .iter()
            .any(|l| path_text(&l.path) == path_text(p) || Some(l.name()) == last);
        if !found {
            let last = p
                .segments
                .last()
                .map(|s| s.ident.to_string())
                .unwrap_or_default();
            return Err(Error::new(
                syn::spanned::Spanned::span(p),
                format!("no library `{last}` was found for this `uses(..)` path"),
            ));
        }
    }
    items::lower_axes(&mut m, &args)?;
    for lib in libs {
        libs::check_axes(&m, lib)?;
    }
    let merged = libs::merged_items(libs, content);
    items::lower_items(&mut m, &merged, mode)?;
    items::lower_predicates(&mut m, &args)?;
    if mode == Mode::Declarations {
        for s in &mut m.module.structs {
            s.uses.io = s.fields.iter().any(|f| f.io.is_some());
        }
    } else {
        checks::check_module(&mut m)?;
    }
    Ok(m.module)
}
