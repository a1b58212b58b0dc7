//! The proc-macro expansions, as plain functions from tokens to tokens (`shader-dsl` only
//! forwards to them).
//!
//! A proc-macro cannot read another item, so libraries travel by callback: `#[library]` emits,
//! inside the library's generated module, a hidden `macro_rules! __shader_library` that
//! forwards the library's own tokens (with their original spans) to `__with_library!`. A
//! `#[shader(.., uses(a, b))]` module expands to `a::__shader_library! { state }`, whose
//! expansion calls `__with_library! { state library { .. } }`, which calls
//! `b::__shader_library!`, and so on; the last step compiles the module with every library.

use crate::front::Library;
use crate::link::{compile_linked, declarations_linked};
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
    for p in &uses {
        let rooted =
            p.leading_colon.is_some() || p.segments.first().is_some_and(|s| s.ident == "crate");
        if !rooted {
            return Err(syn::Error::new(
                p.span(),
                "a library path in `uses(..)` must start at the crate root: write `crate::path::to::library` (the path is resolved from the module that uses it, through the library's hidden `__shader_library` macro)",
            ));
        }
    }
    Ok(next_step(&State {
        args,
        item: item.into_token_stream(),
        pending: uses,
        done: vec![],
    }))
}

/// `#[library(..)]`: compiles and validates the library on its own, and emits its host items
/// plus the hidden `__shader_library` macro. Errors come with a stub of the module (host items
/// when its declarations lower, and the macro, so that users add no follow-on errors).
pub fn expand_library(args: TokenStream, item: TokenStream) -> TokenStream {
    let module: syn::ItemMod = match syn::parse2(item.clone()) {
        Ok(m) => m,
        Err(e) => return e.to_compile_error(),
    };
    match compile_library(args.clone(), &module) {
        Ok(c) => crate::emit::emit_library(&module, &args, &item, Some(&c), None),
        Err(err) => {
            let decls = crate::front::lower_with(
                args.clone(),
                &module,
                &[],
                crate::front::Mode::Declarations,
            )
            .ok()
            .and_then(|m| crate::pipeline::with_keys(m).ok());
            crate::emit::emit_library(&module, &args, &item, decls.as_ref(), Some(err))
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
    state.done.push(step.library);
    if !state.pending.is_empty() {
        return next_step(&state);
    }
    let item: syn::ItemMod = match syn::parse2(state.item.clone()) {
        Ok(m) => m,
        Err(e) => return e.to_compile_error(),
    };
    match compile_linked(state.args.clone(), &item, &state.done) {
        Ok(c) => crate::emit::emit(&item, &c),
        Err(err) => {
            let mut out = err.to_compile_error();
            let decls = declarations_linked(state.args.clone(), &item, &state.done)
                .or_else(|| declarations(TokenStream::new(), &item));
            out.extend(crate::emit::stub(&item, decls.as_ref()));
            out
        }
    }
}

/// The chain's state: the using module, the libraries still to visit, those collected.
struct State {
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
    let done = s.done.iter().map(|l| {
        let (p, a, i) = (&l.path, &l.args, &l.item);
        quote!({ #p } { #a } { #i })
    });
    // The macro's name carries the span of the path's last segment, so that a path that is not
    // a library fails there ("cannot find `__shader_library` in `name`").
    let at = next
        .segments
        .last()
        .map_or_else(Span::call_site, |s| s.ident.span());
    let mac = Ident::new("__shader_library", at);
    quote! {
        #next::#mac! {
            shader { #args } { #item }
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
        keyword(input, "shader")?;
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
            done.push(Library { path, args, item });
        }
        keyword(input, "library")?;
        let largs = braced(input)?;
        let litem = syn::parse2(braced(input)?)?;
        Ok(Step {
            state: State {
                args,
                item,
                pending,
                done,
            },
            library: Library {
                path: calling,
                args: largs,
                item: litem,
            },
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
