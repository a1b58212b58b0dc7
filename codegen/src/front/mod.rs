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
mod ops;
mod resources;
mod signature;
mod statics;
mod stmt;
mod types;

pub(crate) use attrs::is_subgroup_builtin;
pub(crate) use checks::mentions_axis;

pub(crate) use ctx::{FnCtx, ModCtx};

use crate::ir::Module;
use proc_macro2::TokenStream;
use std::collections::HashMap;
use syn::{Error, Result};

/// Lowers a shader module: the attribute arguments and the `mod` item.
pub fn lower(args: TokenStream, item: &syn::ItemMod) -> Result<Module> {
    lower_impl(args, item, false)
}

/// Lowers only the declarations the host side sees (axes, structs, consts, statics), skipping
/// functions and whole-module checks. Used to emit a useful stub next to an error.
pub fn lower_declarations(args: TokenStream, item: &syn::ItemMod) -> Result<Module> {
    lower_impl(args, item, true)
}

fn lower_impl(args: TokenStream, item: &syn::ItemMod, declarations_only: bool) -> Result<Module> {
    let args = args::parse_args(args)?;
    let mut m = ModCtx {
        module: Module {
            name: item.ident.to_string(),
            span: item.ident.span(),
            axes: vec![],
            excludes: vec![],
            requires_subgroup: None,
            structs: vec![],
            consts: vec![],
            globals: vec![],
            functions: vec![],
        },
        struct_ids: HashMap::new(),
        const_ids: HashMap::new(),
        global_ids: HashMap::new(),
        fn_ids: HashMap::new(),
        calls: vec![],
        names: HashMap::new(),
    };
    let Some((_, content)) = &item.content else {
        return Err(Error::new(
            item.ident.span(),
            "a shader module must be inline: `mod name { .. }`",
        ));
    };
    items::lower_axes(&mut m, &args)?;
    items::lower_items(&mut m, content, declarations_only)?;
    items::lower_predicates(&mut m, &args)?;
    if declarations_only {
        for s in &mut m.module.structs {
            s.uses.io = s.fields.iter().any(|f| f.io.is_some());
        }
    } else {
        checks::check_module(&mut m)?;
    }
    Ok(m.module)
}
