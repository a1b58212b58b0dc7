//! Parses the `#[shader(..)]` and `#[library(..)]` arguments: `axes(..)`, `exclude(..)`,
//! `requires(..)` and `uses(..)`.
//!
//! Only syntax lives here; predicates are lowered to IR by the expression lowering like any
//! other constant expression. Must not look at the module body.

use proc_macro2::{Span, TokenStream};
use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::{Ident, LitStr, Token};

/// One axis declaration: `name: ty = [values] (=> "label" (unless value)?)?`.
pub(crate) struct AxisDecl {
    pub name: Ident,
    pub ty: Ident,
    pub values: Vec<syn::Expr>,
    pub label: Option<LitStr>,
    /// `unless value`: the value that adds nothing to variant names.
    pub unless: Option<syn::Expr>,
}

/// The parsed macro arguments.
#[derive(Default)]
pub(crate) struct ShaderArgs {
    pub axes: Vec<AxisDecl>,
    pub excludes: Vec<syn::Expr>,
    /// `(capability name, predicate)`; a bare `requires(subgroup)` gives `None`.
    pub requires: Vec<(Ident, Option<syn::Expr>)>,
    /// `uses(path, ..)`: the libraries merged into the module, in order.
    pub uses: Vec<syn::Path>,
}

impl Parse for AxisDecl {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let name: Ident = input.parse()?;
        input.parse::<Token![:]>()?;
        let ty: Ident = input.parse()?;
        input.parse::<Token![=]>()?;
        let content;
        syn::bracketed!(content in input);
        let values = Punctuated::<syn::Expr, Token![,]>::parse_terminated(&content)?;
        let mut unless = None;
        let label = if input.peek(Token![=>]) {
            input.parse::<Token![=>]>()?;
            let label = input.parse()?;
            if input.peek(Ident) {
                let word: Ident = input.parse()?;
                if word != "unless" {
                    return Err(syn::Error::new(
                        word.span(),
                        "expected `unless value` (the axis value that adds nothing to variant names) or `,`",
                    ));
                }
                unless = Some(input.parse()?);
            }
            Some(label)
        } else {
            None
        };
        Ok(AxisDecl {
            name,
            ty,
            values: values.into_iter().collect(),
            label,
            unless,
        })
    }
}

struct Requirement(Ident, Option<syn::Expr>);

impl Parse for Requirement {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let name: Ident = input.parse()?;
        let pred = if input.peek(Token![=]) {
            input.parse::<Token![=]>()?;
            Some(input.parse()?)
        } else {
            None
        };
        Ok(Requirement(name, pred))
    }
}

impl Parse for ShaderArgs {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let mut args = ShaderArgs::default();
        while !input.is_empty() {
            let key: Ident = input.parse()?;
            let content;
            syn::parenthesized!(content in input);
            match key.to_string().as_str() {
                "axes" => {
                    let axes = Punctuated::<AxisDecl, Token![,]>::parse_terminated(&content)?;
                    args.axes.extend(axes);
                }
                "exclude" => {
                    let preds = Punctuated::<syn::Expr, Token![,]>::parse_terminated(&content)?;
                    args.excludes.extend(preds);
                }
                "requires" => {
                    let reqs = Punctuated::<Requirement, Token![,]>::parse_terminated(&content)?;
                    args.requires.extend(reqs.into_iter().map(|r| (r.0, r.1)));
                }
                "uses" => {
                    let paths = Punctuated::<syn::Path, Token![,]>::parse_terminated(&content)?;
                    args.uses.extend(paths);
                }
                other => {
                    return Err(syn::Error::new(
                        key.span(),
                        format!(
                            "unknown shader argument `{other}`; expected `axes(..)`, `exclude(..)`, `requires(..)` or `uses(..)`"
                        ),
                    ));
                }
            }
            if !input.is_empty() {
                input.parse::<Token![,]>()?;
            }
        }
        Ok(args)
    }
}

/// Parses the attribute arguments.
pub(crate) fn parse_args(tokens: TokenStream) -> syn::Result<ShaderArgs> {
    syn::parse2(tokens)
}

/// A `static NAME: Type;` item (which syn keeps as verbatim tokens).
pub(crate) struct BareStatic {
    pub attrs: Vec<syn::Attribute>,
    pub mutability: bool,
    pub ident: Ident,
    pub ty: syn::Type,
    pub value: Option<Span>,
}

impl Parse for BareStatic {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let attrs = input.call(syn::Attribute::parse_outer)?;
        let _vis: syn::Visibility = input.parse()?;
        input.parse::<Token![static]>()?;
        let mutability = input.parse::<Option<Token![mut]>>()?.is_some();
        let ident: Ident = input.parse()?;
        input.parse::<Token![:]>()?;
        let ty: syn::Type = input.parse()?;
        let value = if input.peek(Token![=]) {
            let eq = input.parse::<Token![=]>()?;
            input.parse::<syn::Expr>()?;
            Some(eq.span)
        } else {
            None
        };
        input.parse::<Token![;]>()?;
        Ok(BareStatic {
            attrs,
            mutability,
            ident,
            ty,
            value,
        })
    }
}
