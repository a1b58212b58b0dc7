//! Libraries seen from the module that uses them: the `Library` a using module is given, the
//! checks that the module can host it (its axes), and the merged item list (library items
//! first, dependencies before their users, tagged with the library they came from). Lowering
//! itself is `items`' job; ordering the library graph is `lib_graph`'s.

use super::args::{ShaderArgs, parse_args};
use super::ctx::ModCtx;
use super::items::lower_axes;
use crate::ir::Lit;
use proc_macro2::TokenStream;
use syn::spanned::Spanned;
use syn::{Error, Result};

/// A library as a using module receives it: the path written in `uses(..)` and the library's
/// own attribute arguments and `mod` item (with their original spans).
#[derive(Debug, Clone)]
pub struct Library {
    /// The path in `uses(..)` that named it (the module's own, or a library's for a library
    /// reached through another).
    pub path: syn::Path,
    /// The `#[library(..)]` arguments.
    pub args: TokenStream,
    /// The library module, its `#[library]` attribute removed.
    pub item: syn::ItemMod,
    /// The `uses(..)` paths from the compiled module down to this library, the module's own
    /// first: one path for a library the module names itself. Set by the graph ordering.
    pub route: Vec<syn::Path>,
    /// The libraries this one uses itself, as indices into the ordered list (all before it).
    /// Set by the graph ordering.
    pub uses: Vec<usize>,
}

impl Library {
    /// A library reached through `path`, before the graph is ordered.
    pub fn new(path: syn::Path, args: TokenStream, item: syn::ItemMod) -> Self {
        Library {
            route: vec![path.clone()],
            path,
            args,
            item,
            uses: vec![],
        }
    }

    /// The library's module name.
    pub fn name(&self) -> String {
        self.item.ident.to_string()
    }

    /// The libraries this library's own `uses(..)` names.
    pub fn uses_paths(&self) -> Result<Vec<syn::Path>> {
        Ok(parse_args(self.args.clone())?.uses)
    }

    /// How the library is named in errors: "library `name`", with the route when the module
    /// reaches it through other libraries.
    pub fn described(&self) -> String {
        let name = self.name();
        if self.route.len() < 2 {
            format!("library `{name}`")
        } else {
            format!(
                "library `{name}` (used through {})",
                route_text(&self.route)
            )
        }
    }

    /// Where errors about the library as a whole point: the module's own `uses(..)` path that
    /// leads to it.
    pub fn entry_span(&self) -> proc_macro2::Span {
        self.route.first().unwrap_or(&self.path).span()
    }

    /// The library's items (an empty list for a module without a body, which the library's own
    /// compilation already rejected).
    pub fn items(&self) -> &[syn::Item] {
        self.item.content.as_ref().map_or(&[], |(_, c)| c)
    }
}

/// `crate::a → crate::b`: a route through the library graph, as errors print it.
pub(crate) fn route_text(route: &[syn::Path]) -> String {
    route.iter().map(path_text).collect::<Vec<_>>().join(" → ")
}

/// A `uses(..)` path as written, without the token printer's spaces: `crate::shared::pbr`.
pub(crate) fn path_text(p: &syn::Path) -> String {
    quote::ToTokens::to_token_stream(p)
        .to_string()
        .replace(' ', "")
}

/// The checks on a library's own arguments: no `exclude(..)` (a library may use others).
pub(crate) fn check_library_args(args: &ShaderArgs) -> Result<()> {
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
    let name = lib.described();
    for a in &scratch.module.axes {
        let ty = a.ty.rust_name();
        let Some(mine) = m.module.axes.iter().find(|x| x.name == a.name) else {
            return Err(Error::new(
                lib.entry_span(),
                format!(
                    "{name} needs axis `{}: {ty}`; declare it in this module's `axes(..)` (the library supports the values {})",
                    a.name,
                    values_text(&a.values)
                ),
            ));
        };
        if mine.ty != a.ty {
            return Err(Error::new(
                lib.entry_span(),
                format!(
                    "{name} needs axis `{}: {ty}`, but this module declares it as `{}`",
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
                lib.entry_span(),
                format!(
                    "axis `{}` takes the values {} here, which {name} does not support (it supports {})",
                    a.name,
                    values_text(&unsupported),
                    values_text(&a.values)
                ),
            ));
        }
    }
    Ok(())
}

/// The items a using module lowers: each library's items (tagged with how errors name it), in
/// the graph's order, then the module's own (`None`).
pub(crate) fn merged_items<'a>(
    libs: &'a [Library],
    own: &'a [syn::Item],
) -> Vec<(Option<String>, &'a syn::Item)> {
    let mut out = vec![];
    for lib in libs {
        let name = lib.described();
        out.extend(lib.items().iter().map(|i| (Some(name.clone()), i)));
    }
    out.extend(own.iter().map(|i| (None, i)));
    out
}
