//! Finding DSL modules in Rust source text, for tools that compile without the proc-macro
//! (`cargo xtask shaders`, golden tests): `#[shader]` and `#[library]` modules, and `uses(..)`
//! resolved by the path's last segment among the libraries found, through the whole library
//! graph (a library's own `uses(..)` too).

use crate::front::{Library, Root};
use crate::link::{compile_library_linked, compile_linked};
use crate::pipeline::Compiled;
use proc_macro2::TokenStream;

/// Every `#[shader(..)]` module of a Rust source file (at any nesting depth), with its
/// attribute arguments, the attribute removed; and every `#[material(..)]` module as the
/// `#[shader(..)]` module it expands to (`material::as_shader`; one that does not expand is
/// left as written, so compiling it reports its arguments).
pub fn shader_modules(file: &syn::File) -> Vec<(TokenStream, syn::ItemMod)> {
    let mut out = modules_with(file, "shader");
    for (args, item) in modules_with(file, "material") {
        out.push(crate::material::as_shader(args.clone(), item.clone()).unwrap_or((args, item)));
    }
    out
}

/// Every `#[library(..)]` module of a Rust source file, like [`shader_modules`].
pub fn library_modules(file: &syn::File) -> Vec<(TokenStream, syn::ItemMod)> {
    modules_with(file, "library")
}

fn modules_with(file: &syn::File, attr_name: &str) -> Vec<(TokenStream, syn::ItemMod)> {
    let is_it = |a: &syn::Attribute| {
        a.path()
            .segments
            .last()
            .is_some_and(|s| s.ident == attr_name)
    };
    fn walk(
        items: &[syn::Item],
        is_it: &dyn Fn(&syn::Attribute) -> bool,
        out: &mut Vec<(TokenStream, syn::ItemMod)>,
    ) {
        for item in items {
            let syn::Item::Mod(m) = item else { continue };
            if let Some(attr) = m.attrs.iter().find(|a| is_it(a)) {
                let args = match &attr.meta {
                    syn::Meta::List(l) => l.tokens.clone(),
                    _ => TokenStream::new(),
                };
                let mut item = m.clone();
                item.attrs.retain(|a| !is_it(a));
                out.push((args, item));
            } else if let Some((_, content)) = &m.content {
                walk(content, is_it, out);
            }
        }
    }
    let mut out = vec![];
    walk(&file.items, &is_it, &mut out);
    out
}

/// The `#[library]` modules of several source texts (for [`compile_with_libraries`]).
pub fn libraries_of(sources: &[&str]) -> syn::Result<Vec<(TokenStream, syn::ItemMod)>> {
    let mut out = vec![];
    for src in sources {
        out.extend(library_modules(&syn::parse_file(src)?));
    }
    Ok(out)
}

/// Compiles every `#[shader(..)]` module of Rust source text (tools such as
/// `cargo xtask shaders`, which also want per-variant timings): `(module name, result)`. The
/// libraries its modules use must be in the same text; see [`compile_source_all_with`].
pub fn compile_source_all(src: &str) -> syn::Result<Vec<(String, syn::Result<Compiled>)>> {
    compile_source_all_with(src, &[])
}

/// [`compile_source_all`], with `uses(..)` resolved among the `#[library]` modules of `src`
/// and of `library_sources` (by the path's last segment).
pub fn compile_source_all_with(
    src: &str,
    library_sources: &[&str],
) -> syn::Result<Vec<(String, syn::Result<Compiled>)>> {
    let file = syn::parse_file(src)?;
    let mut libs = library_modules(&file);
    libs.extend(libraries_of(library_sources)?);
    Ok(shader_modules(&file)
        .into_iter()
        .map(|(args, item)| {
            let r = compile_with_libraries(args, &item, &libs);
            (item.ident.to_string(), r)
        })
        .collect())
}

/// Compiles the first `#[shader(..)]` module found in Rust source text (golden tests, tools),
/// with the libraries of the same text.
pub fn compile_source(src: &str) -> syn::Result<Compiled> {
    let file = syn::parse_file(src)?;
    let libs = library_modules(&file);
    match shader_modules(&file).into_iter().next() {
        Some((args, item)) => compile_with_libraries(args, &item, &libs),
        None => Err(syn::Error::new(
            proc_macro2::Span::call_site(),
            "no `#[shader(..)] mod` found",
        )),
    }
}

/// Compiles a shader module, finding each library of its `uses(..)` by the path's last segment
/// among `available` (`#[library]` modules with their arguments, as [`library_modules`] gives
/// them): for tools that compile source text, where no macro resolves the paths.
pub fn compile_with_libraries(
    args: TokenStream,
    item: &syn::ItemMod,
    available: &[(TokenStream, syn::ItemMod)],
) -> syn::Result<Compiled> {
    let libs = resolve_libraries(args.clone(), item, available)?;
    compile_linked(args, item, &libs)
}

/// Compiles a `#[library]` module on its own over its axes, finding the libraries it uses (and
/// those they use) among `available` as [`compile_with_libraries`] does.
pub fn compile_library_with_libraries(
    args: TokenStream,
    item: &syn::ItemMod,
    available: &[(TokenStream, syn::ItemMod)],
) -> syn::Result<Compiled> {
    let uses = crate::front::uses_of(args.clone())?;
    let root = Root {
        name: item.ident.to_string(),
        uses: &uses,
        library_item: Some(item),
    };
    let libs = resolve_graph(&root, available)?;
    compile_library_linked(args, item, &libs)
}

fn resolve_libraries(
    args: TokenStream,
    item: &syn::ItemMod,
    available: &[(TokenStream, syn::ItemMod)],
) -> syn::Result<Vec<Library>> {
    let uses = crate::front::uses_of(args)?;
    let root = Root {
        name: item.ident.to_string(),
        uses: &uses,
        library_item: None,
    };
    resolve_graph(&root, available)
}

/// The library graph `root` reaches among `available`, each path resolved by its last segment.
fn resolve_graph(
    root: &Root,
    available: &[(TokenStream, syn::ItemMod)],
) -> syn::Result<Vec<Library>> {
    let candidates: Vec<Library> = available
        .iter()
        .map(|(args, item)| {
            let path = syn::Path::from(item.ident.clone());
            Library::new(path, args.clone(), item.clone())
        })
        .collect();
    let resolve = |path: &syn::Path| {
        let last = path.segments.last().map(|s| s.ident.to_string());
        candidates
            .iter()
            .position(|l| Some(l.name()) == last)
            .ok_or_else(|| {
                syn::Error::new(
                    syn::spanned::Spanned::span(path),
                    format!(
                        "no `#[library]` module named `{}` in the sources given",
                        last.unwrap_or_default()
                    ),
                )
            })
    };
    crate::front::order(root, &candidates, &resolve)
}
