//! Libraries seen from the module that uses them: the `Library` a using module is given, the
//! checks that the module can host it (its axes), and the merged item list (library items
//! first, tagged with the library they came from). Lowering itself is `items`' job.

use super::args::{ShaderArgs, parse_args};
use super::ctx::ModCtx;
use super::items::lower_axes;
use crate::ir::Lit;
use proc_macro2::TokenStream;
use syn::spanned::Spanned;
use syn::{Error, Result};

/// A library as a using module receives it: the path the module wrote in `uses(..)` and the
/// library's own attribute arguments and `mod` item (with their original spans).
#[derive(Debug, Clone)]
pub struct Library {
    /// The path in `uses(..)`; errors about the library as a whole point here.
    pub path: syn::Path,
    /// The `#[library(..)]` arguments.
    pub args: TokenStream,
    /// The library module, its `#[library]` attribute removed.
    pub item: syn::ItemMod,
}

impl Library {
    /// The library's module name.
    pub fn name(&self) -> String {
        self.item.ident.to_string()
    }

    /// The library's items (an empty list for a module without a body, which the library's own
    /// compilation already rejected).
    pub fn items(&self) -> &[syn::Item] {
        self.item.content.as_ref().map_or(&[], |(_, c)| c)
    }
}

/// The checks on a library's own arguments: no `uses(..)`, no `exclude(..)`.
pub(crate) fn check_library_args(args: &ShaderArgs) -> Result<()> {
    if let Some(p) = args.uses.first() {
        return Err(Error::new(
            p.span(),
            "a library cannot use another library; list every library in the using shader module's `uses(..)`",
        ));
    }
    if let Some(e) = args.excludes.first() {
        return Err(Error::new(
            e.span(),
            "`exclude(..)` belongs to the shader modules that use this library, not to the library",
        ));
    }
    Ok(())
}

fn values_text(values: &[Lit]) -> String {
    let v: Vec<String> = values
        .iter()
        .map(|l| match l {
            Lit::Bool(b) => b.to_string(),
            Lit::Int(i, _) => i.to_string(),
            Lit::Float(f, _) => f.to_string(),
        })
        .collect();
    format!("[{}]", v.join(", "))
}

/// Every axis the library declares must be an axis of the using module, of the same type,
/// whose values the library supports. Errors point at the library's path in `uses(..)`.
pub(crate) fn check_axes(m: &ModCtx, lib: &Library) -> Result<()> {
    let args = parse_args(lib.args.clone())?;
    let mut scratch = ModCtx::new(&lib.item);
    lower_axes(&mut scratch, &args)?;
    let name = lib.name();
    for a in &scratch.module.axes {
        let ty = a.ty.rust_name();
        let Some(mine) = m.module.axes.iter().find(|x| x.name == a.name) else {
            return Err(Error::new(
                lib.path.span(),
                format!(
                    "library `{name}` needs axis `{}: {ty}`; declare it in this module's `axes(..)` (the library supports the values {})",
                    a.name,
                    values_text(&a.values)
                ),
            ));
        };
        if mine.ty != a.ty {
            return Err(Error::new(
                lib.path.span(),
                format!(
                    "library `{name}` needs axis `{}: {ty}`, but this module declares it as `{}`",
                    a.name,
                    mine.ty.rust_name()
                ),
            ));
        }
        let unsupported: Vec<Lit> = mine
            .values
            .iter()
            .filter(|v| !a.values.contains(v))
            .copied()
            .collect();
        if !unsupported.is_empty() {
            return Err(Error::new(
                lib.path.span(),
                format!(
                    "axis `{}` takes the values {} here, which library `{name}` does not support (it supports {})",
                    a.name,
                    values_text(&unsupported),
                    values_text(&a.values)
                ),
            ));
        }
    }
    Ok(())
}

/// The items a using module lowers: each library's items (tagged with its name), then the
/// module's own (`None`).
pub(crate) fn merged_items<'a>(
    libs: &'a [Library],
    own: &'a [syn::Item],
) -> Vec<(Option<String>, &'a syn::Item)> {
    let mut out = vec![];
    for lib in libs {
        let name = lib.name();
        out.extend(lib.items().iter().map(|i| (Some(name.clone()), i)));
    }
    out.extend(own.iter().map(|i| (None, i)));
    out
}
