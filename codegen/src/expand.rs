//! The proc-macro expansions, as plain functions from tokens to tokens (`shader-dsl` only
//! forwards to them).
//!
//! A proc-macro cannot read another item, so libraries travel by callback: `#[library]` emits,
//! inside the library's generated module, a hidden `macro_rules! __shader_library` that
//! forwards the library's own tokens (with their original spans) to `__with_library!`. A
//! `#[shader(.., uses(a, b))]` module expands to `a::__shader_library! { state }`, whose
//! expansion calls `__with_library! { state library { .. } }`, which calls
//! `b::__shader_library!`, and so on; the last step compiles the module with every library.
//!
//! A library may use libraries too. Each step adds the `uses(..)` of the library it received
//! to the paths still to visit (each path once), so the chain collects the whole graph; the
//! last step orders it (`front::order`: dependencies first, cycles refused) before compiling.
//! A `#[library(uses(..))]` emits its forwarding macro at once, so modules can reach it, and
//! starts a chain of its own inside its module whose last step validates the library with what
//! it uses and emits its host items there.

use crate::front::{Library, Root, by_full_path, order, path_text};
use crate::link::{
    compile_library_linked, compile_linked, declarations_linked, library_declarations_linked,
};
use crate::pipeline::{compile, compile_library, declarations};
use proc_macro2::{Span, TokenStream};
use quote::{ToTokens, quote};
use syn::parse::{Parse, ParseStream};
use syn::spanned::Spanned;
use syn::{Ident, Token};

/// `#[shader(..)]`: compiles and emits the generated Rust module, or, with `uses(..)`, starts
/// the chain that collects the libraries.
pub fn expand(args: TokenStream, item: TokenStream) -> syn::Result<TokenStream> {
    let item: syn::ItemMod = syn::parse2(item)?;
    let uses = crate::front::uses_of(args.clone())?;
    if uses.is_empty() {
        let compiled = compile(args, &item)?;
        return Ok(crate::emit::emit(&item, &compiled));
    }
    check_rooted(&uses)?;
    Ok(next_step(&State {
        target: Target::Shader,
        args,
        item: item.into_token_stream(),
        pending: uses,
        done: vec![],
    }))
}

/// Every path in `uses(..)` must start at a crate root: `crate::` for a library of this crate,
/// a crate's name for a library of a dependency (the chain resolves it from wherever the using
/// module is).
fn check_rooted(uses: &[syn::Path]) -> syn::Result<()> {
    for p in uses {
        let first = p.segments.first().map(|s| s.ident.to_string());
        let relative = matches!(first.as_deref(), Some("self" | "super" | "Self"));
        if relative || p.segments.len() < 2 {
            return Err(syn::Error::new(
                p.span(),
                "a library path in `uses(..)` must start at a crate root: write `crate::path::to::library` for a library of this crate, or `other_crate::path::to::library` for one of a dependency (the path is resolved from the module that uses it, through the library's hidden macros)",
            ));
        }
    }
    Ok(())
}

/// Whether `path` names a library of the crate being compiled (`crate::..`), whose module
/// holds the crate-local forwarding macro; otherwise the library is another crate's, reached
/// through the macro that crate exports at its root.
fn in_this_crate(path: &syn::Path) -> bool {
    path.leading_colon.is_none() && path.segments.first().is_some_and(|s| s.ident == "crate")
}

/// `#[library(..)]`: compiles and validates the library on its own, and emits its host items
/// plus the hidden `__shader_library` macro. Errors come with a stub of the module (host items
/// when its declarations lower, and the macro, so that users add no follow-on errors).
pub fn expand_library(args: TokenStream, item: TokenStream) -> TokenStream {
    let module: syn::ItemMod = match syn::parse2(item.clone()) {
        Ok(m) => m,
        Err(e) => return e.to_compile_error(),
    };
    let uses = match crate::front::uses_of(args.clone()).and_then(|u| {
        check_rooted(&u)?;
        Ok(u)
    }) {
        Ok(u) => u,
        Err(e) => return crate::emit::emit_library(&module, &args, &item, quote!(), Some(e)),
    };
    if !uses.is_empty() {
        let chain = next_step(&State {
            target: Target::Library,
            args: args.clone(),
            item: item.clone(),
            pending: uses,
            done: vec![],
        });
        return crate::emit::emit_library(&module, &args, &item, chain, None);
    }
    match compile_library(args.clone(), &module) {
        Ok(c) => {
            let body = crate::emit::library_host_items(&c);
            crate::emit::emit_library(&module, &args, &item, body, None)
        }
        Err(err) => {
            let decls = crate::front::lower_with(
                args.clone(),
                &module,
                &[],
                crate::front::Mode::Declarations,
            )
            .ok()
            .and_then(|m| crate::pipeline::with_keys(m).ok());
            let body = decls
                .as_ref()
                .map(crate::emit::library_host_items)
                .unwrap_or_default();
            crate::emit::emit_library(&module, &args, &item, body, Some(err))
        }
    }
}

/// `__with_library!`: one step of the chain (see the module documentation).
pub fn expand_with_library(input: TokenStream) -> TokenStream {
    let step: Step = match syn::parse2(input) {
        Ok(s) => s,
        Err(e) => return e.to_compile_error(),
    };
    let mut state = step.state;
    match step.library.uses_paths() {
        Ok(deps) => {
            for dep in deps {
                let text = path_text(&dep);
                let seen = path_text(&step.library.path) == text
                    || state.done.iter().any(|l| path_text(&l.path) == text)
                    || state.pending.iter().any(|p| path_text(p) == text);
                if !seen {
                    state.pending.push(dep);
                }
            }
        }
        Err(e) => return e.to_compile_error(),
    }
    state.done.push(step.library);
    if !state.pending.is_empty() {
        return next_step(&state);
    }
    let item: syn::ItemMod = match syn::parse2(state.item.clone()) {
        Ok(m) => m,
        Err(e) => return e.to_compile_error(),
    };
    match state.target {
        Target::Shader => finish_shader(&state, &item),
        Target::Library => finish_library(&state, &item),
    }
}

/// The collected graph in merge order (see `front::order`).
fn ordered(state: &State, item: &syn::ItemMod, library: bool) -> syn::Result<Vec<Library>> {
    let uses = crate::front::uses_of(state.args.clone())?;
    let root = Root {
        name: item.ident.to_string(),
        uses: &uses,
        library_item: library.then_some(item),
    };
    order(&root, &state.done, &by_full_path(&state.done))
}

/// The last step for a `#[shader]` module: the generated module, or the error and a stub.
fn finish_shader(state: &State, item: &syn::ItemMod) -> TokenStream {
    let compiled = ordered(state, item, false)
        .and_then(|libs| compile_linked(state.args.clone(), item, &libs));
    match compiled {
        Ok(c) => crate::emit::emit(item, &c),
        Err(err) => {
            let mut out = err.to_compile_error();
            let decls = ordered(state, item, false)
                .ok()
                .and_then(|libs| declarations_linked(state.args.clone(), item, &libs))
                .or_else(|| declarations(TokenStream::new(), item));
            out.extend(crate::emit::stub(item, decls.as_ref()));
            out
        }
    }
}

/// The last step for a `#[library]` that uses libraries, inside its generated module: its host
/// items, or the error (and the host items when its declarations lower).
fn finish_library(state: &State, item: &syn::ItemMod) -> TokenStream {
    let compiled = ordered(state, item, true)
        .and_then(|libs| compile_library_linked(state.args.clone(), item, &libs));
    match compiled {
        Ok(c) => crate::emit::library_host_items(&c),
        Err(err) => {
            let mut out = err.to_compile_error();
            let decls = ordered(state, item, true)
                .ok()
                .and_then(|libs| library_declarations_linked(state.args.clone(), item, &libs));
            if let Some(d) = decls {
                out.extend(crate::emit::library_host_items(&d));
            }
            out
        }
    }
}

/// What the chain compiles at its end.
#[derive(Clone, Copy)]
enum Target {
    /// A `#[shader]` module: the last step emits the generated module.
    Shader,
    /// A `#[library]` that uses libraries: the last step emits its host items.
    Library,
}

/// The chain's state: the using module, the libraries still to visit, those collected.
struct State {
    target: Target,
    args: TokenStream,
    item: TokenStream,
    pending: Vec<syn::Path>,
    done: Vec<Library>,
}

/// `__with_library!`'s input: the state, the path being visited, and what its library sent.
struct Step {
    state: State,
    library: Library,
}

fn next_step(s: &State) -> TokenStream {
    #[expect(
        clippy::expect_used,
        reason = "called only while libraries are pending"
    )]
    let (next, rest) = s.pending.split_first().expect("a library left to visit");
    let (args, item) = (&s.args, &s.item);
    let target = Ident::new(
        match s.target {
            Target::Shader => "shader",
            Target::Library => "library_target",
        },
        Span::call_site(),
    );
    let done = s.done.iter().map(|l| {
        let (p, a, i) = (&l.path, &l.args, &l.item);
        quote!({ #p } { #a } { #i })
    });
    // The macro's name carries the span of the path's last segment, so that a path that is not
    // a library fails there ("cannot find `__shader_library` in `name`").
    let last = next.segments.last();
    let at = last.map_or_else(Span::call_site, |s| s.ident.span());
    let callee = if in_this_crate(next) {
        let mac = Ident::new("__shader_library", at);
        quote!(#next::#mac)
    } else {
        // `other_crate::__shader_library_<name>`, or `$crate::..` for a path that came from
        // another crate's exported macro.
        let name = last.map(|s| s.ident.to_string()).unwrap_or_default();
        let mac = Ident::new(&crate::emit::exported_library_macro(&name), at);
        let root = next.segments.first().map(|s| &s.ident);
        let colon = &next.leading_colon;
        quote!(#colon #root::#mac)
    };
    quote! {
        #callee! {
            #target { #args } { #item }
            pending { #(#rest),* }
            calling { #next }
            done { #(#done)* }
        }
    }
}

fn braced(input: ParseStream) -> syn::Result<TokenStream> {
    let content;
    syn::braced!(content in input);
    content.parse()
}

fn keyword(input: ParseStream, word: &str) -> syn::Result<()> {
    let k: Ident = input.parse()?;
    if k != word {
        return Err(syn::Error::new(
            k.span(),
            format!("internal shader-dsl state: expected `{word}`"),
        ));
    }
    Ok(())
}

impl Parse for Step {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let kind: Ident = input.parse()?;
        let target = match kind.to_string().as_str() {
            "shader" => Target::Shader,
            "library_target" => Target::Library,
            _ => {
                return Err(syn::Error::new(
                    kind.span(),
                    "internal shader-dsl state: expected `shader` or `library_target`",
                ));
            }
        };
        let (args, item) = (braced(input)?, braced(input)?);
        keyword(input, "pending")?;
        let pending = syn::parse2::<PathList>(braced(input)?)?.0;
        keyword(input, "calling")?;
        let calling: syn::Path = syn::parse2(braced(input)?)?;
        keyword(input, "done")?;
        let content;
        syn::braced!(content in input);
        let mut done = vec![];
        while !content.is_empty() {
            let path = syn::parse2(braced(&content)?)?;
            let args = braced(&content)?;
            let item = syn::parse2(braced(&content)?)?;
            done.push(Library::new(path, args, item));
        }
        keyword(input, "library")?;
        let largs = braced(input)?;
        let litem = syn::parse2(braced(input)?)?;
        Ok(Step {
            state: State {
                target,
                args,
                item,
                pending,
                done,
            },
            library: Library::new(calling, largs, litem),
        })
    }
}

struct PathList(Vec<syn::Path>);

impl Parse for PathList {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let list = input.parse_terminated(syn::Path::parse_mod_style, Token![,])?;
        Ok(PathList(list.into_iter().collect()))
    }
}
