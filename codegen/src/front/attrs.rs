//! Parses the DSL's helper attributes on items, parameters and fields.
//!
//! Resource attributes (`#[uniform]`, `#[storage]`, `#[texture]`, `#[sampler]`, `#[workgroup]`),
//! stage attributes (`#[compute]`, `#[vertex]`, `#[fragment]`) and IO attributes (`#[builtin]`,
//! `#[location]`, `#[interpolate]`). Only syntax and argument checking; no typing here.

use crate::ir::Io;
use proc_macro2::Span;
use syn::spanned::Spanned;
use syn::{Attribute, Error, LitInt, Result};

/// Attributes that only document or tune Rust and are accepted and ignored.
fn is_ignored(attr: &Attribute) -> bool {
    let p = attr.path();
    [
        "doc", "allow", "expect", "inline", "derive", "rustfmt", "must_use",
    ]
    .iter()
    .any(|n| p.is_ident(n))
}

fn unexpected(attr: &Attribute, what: &str, allowed: &str) -> Error {
    Error::new(
        attr.path().span(),
        format!("unsupported attribute on {what}; allowed here: {allowed}"),
    )
}

/// A resource or workgroup attribute on a `static`.
pub(crate) struct StaticAttr {
    pub kind: StaticKind,
    pub group_binding: Option<(u32, u32)>,
    pub read_write: bool,
    pub unfilterable: bool,
    pub when: Option<syn::Expr>,
    pub span: Span,
}

#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum StaticKind {
    Uniform,
    Storage,
    Texture,
    Sampler,
    Workgroup,
}

fn lit_u32(lit: &LitInt) -> Result<u32> {
    lit.base10_parse::<u32>()
}

pub(crate) fn static_attr(attrs: &[Attribute], item_span: Span) -> Result<StaticAttr> {
    const ALLOWED: &str = "`#[uniform(group = G, binding = B)]`, `#[storage(group = G, binding = B[, read_write])]`, `#[texture(group = G, binding = B[, unfilterable])]`, `#[sampler(group = G, binding = B)]` or `#[workgroup]`";
    let mut found: Option<StaticAttr> = None;
    let mut when = None;
    for attr in attrs {
        if attr.path().is_ident("when") {
            when =
                Some(attr.parse_args::<syn::Expr>().map_err(|_| {
                    Error::new(attr.meta.span(), "expected `#[when(axis predicate)]`")
                })?);
            continue;
        }
        if is_ignored(attr) {
            continue;
        }
        let kind = match attr.path().get_ident().map(|i| i.to_string()).as_deref() {
            Some("uniform") => StaticKind::Uniform,
            Some("storage") => StaticKind::Storage,
            Some("texture") => StaticKind::Texture,
            Some("sampler") => StaticKind::Sampler,
            Some("workgroup") => StaticKind::Workgroup,
            _ => return Err(unexpected(attr, "a `static`", ALLOWED)),
        };
        if found.is_some() {
            return Err(Error::new(
                attr.meta.span(),
                "a `static` takes exactly one resource attribute",
            ));
        }
        let mut out = StaticAttr {
            kind,
            group_binding: None,
            read_write: false,
            unfilterable: false,
            when: None,
            span: attr.meta.span(),
        };
        if kind == StaticKind::Workgroup {
            if !matches!(attr.meta, syn::Meta::Path(_)) {
                return Err(Error::new(
                    attr.meta.span(),
                    "`#[workgroup]` takes no arguments",
                ));
            }
            found = Some(out);
            continue;
        }
        let (mut group, mut binding) = (None, None);
        let name = attr
            .path()
            .get_ident()
            .map(|i| i.to_string())
            .unwrap_or_default();
        attr.parse_nested_meta(|meta| {
            if meta.path.is_ident("group") {
                group = Some(lit_u32(&meta.value()?.parse()?)?);
            } else if meta.path.is_ident("binding") {
                binding = Some(lit_u32(&meta.value()?.parse()?)?);
            } else if meta.path.is_ident("read_write") && kind == StaticKind::Storage {
                out.read_write = true;
            } else if meta.path.is_ident("unfilterable") && kind == StaticKind::Texture {
                out.unfilterable = true;
            } else {
                let extra = match kind {
                    StaticKind::Storage => ", `read_write`",
                    StaticKind::Texture => ", `unfilterable`",
                    _ => "",
                };
                return Err(meta.error(format!(
                    "unknown argument of `#[{name}]`; expected `group = N`, `binding = N`{extra}"
                )));
            }
            Ok(())
        })
        .map_err(|e| {
            if matches!(attr.meta, syn::Meta::Path(_)) {
                Error::new(
                    attr.meta.span(),
                    format!("`#[{name}]` needs `(group = G, binding = B)`"),
                )
            } else {
                e
            }
        })?;
        match (group, binding) {
            (Some(g), Some(b)) => out.group_binding = Some((g, b)),
            (None, _) => {
                return Err(Error::new(
                    attr.meta.span(),
                    format!("`#[{name}]` is missing `group = N`"),
                ));
            }
            (_, None) => {
                return Err(Error::new(
                    attr.meta.span(),
                    format!("`#[{name}]` is missing `binding = N`"),
                ));
            }
        }
        found = Some(out);
    }
    let mut found = found.ok_or_else(|| {
        Error::new(
            item_span,
            format!("a `static` in a shader module needs a resource attribute: {ALLOWED}"),
        )
    })?;
    found.when = when;
    Ok(found)
}

/// The message for `#[invariant]` anywhere but on a position builtin.
pub(crate) const INVARIANT_MISPLACED: &str = "`#[invariant]` applies only to the position: a `#[builtin(position)]` field or parameter, or a `#[vertex]` function that returns its position as `Vec4`";

/// Whether a `fn` carries `#[invariant]` (its returned position is invariant), and where.
pub(crate) fn fn_invariant(attrs: &[Attribute]) -> Option<Span> {
    attrs
        .iter()
        .find(|a| a.path().is_ident("invariant"))
        .map(|a| a.meta.span())
}

/// `#[when(predicate)]` on a `fn`, with its span: the entry point exists only in variants
/// where the predicate holds.
pub(crate) fn fn_when(attrs: &[Attribute]) -> Result<Option<(syn::Expr, Span)>> {
    let mut found = None;
    for attr in attrs.iter().filter(|a| a.path().is_ident("when")) {
        if found.is_some() {
            return Err(Error::new(
                attr.meta.span(),
                "a function takes one `#[when(..)]`; join the predicates with `&&`",
            ));
        }
        let e = attr
            .parse_args::<syn::Expr>()
            .map_err(|_| Error::new(attr.meta.span(), "expected `#[when(axis predicate)]`"))?;
        found = Some((e, attr.meta.span()));
    }
    Ok(found)
}

/// Stage attribute on a `fn`.
pub(crate) enum StageAttr {
    Compute(Vec<syn::Expr>, Span),
    Vertex,
    Fragment,
}

pub(crate) fn fn_stage(attrs: &[Attribute]) -> Result<Option<StageAttr>> {
    const ALLOWED: &str = "`#[compute(workgroup_size(x, y, z))]`, `#[vertex]` or `#[fragment]`";
    let mut stage = None;
    for attr in attrs {
        if is_ignored(attr) || attr.path().is_ident("invariant") || attr.path().is_ident("when") {
            continue;
        }
        let s = if attr.path().is_ident("compute") {
            let mut sizes = None;
            attr.parse_nested_meta(|meta| {
                if meta.path.is_ident("workgroup_size") {
                    let content;
                    syn::parenthesized!(content in meta.input);
                    let list = content.parse_terminated(syn::Expr::parse, syn::Token![,])?;
                    sizes = Some(list.into_iter().collect::<Vec<_>>());
                    Ok(())
                } else {
                    Err(meta.error("expected `workgroup_size(x, y, z)`"))
                }
            })
            .map_err(|e| {
                if matches!(attr.meta, syn::Meta::Path(_)) {
                    Error::new(
                        attr.meta.span(),
                        "`#[compute]` needs `(workgroup_size(x, y, z))`",
                    )
                } else {
                    e
                }
            })?;
            let sizes = sizes.unwrap_or_default();
            if sizes.is_empty() || sizes.len() > 3 {
                return Err(Error::new(
                    attr.meta.span(),
                    "`workgroup_size` takes one to three sizes",
                ));
            }
            StageAttr::Compute(sizes, attr.meta.span())
        } else if attr.path().is_ident("vertex") || attr.path().is_ident("fragment") {
            if !matches!(attr.meta, syn::Meta::Path(_)) {
                return Err(Error::new(
                    attr.meta.span(),
                    "stage attributes take no arguments here",
                ));
            }
            if attr.path().is_ident("vertex") {
                StageAttr::Vertex
            } else {
                StageAttr::Fragment
            }
        } else {
            return Err(unexpected(attr, "a `fn`", ALLOWED));
        };
        if stage.is_some() {
            return Err(Error::new(
                attr.meta.span(),
                "a function can have only one stage attribute",
            ));
        }
        stage = Some(s);
    }
    Ok(stage)
}

use syn::parse::Parse;

/// The WGSL builtins the DSL accepts, with the type each must have (DSL spelling).
pub(crate) const BUILTINS: &[(&str, &str)] = &[
    ("position", "Vec4"),
    ("vertex_index", "u32"),
    ("instance_index", "u32"),
    ("front_facing", "bool"),
    ("frag_depth", "f32"),
    ("sample_index", "u32"),
    ("sample_mask", "u32"),
    ("local_invocation_id", "UVec3"),
    ("local_invocation_index", "u32"),
    ("global_invocation_id", "UVec3"),
    ("workgroup_id", "UVec3"),
    ("num_workgroups", "UVec3"),
    ("subgroup_size", "u32"),
    ("subgroup_invocation_id", "u32"),
];

const INTERP_TYPES: &[&str] = &["perspective", "linear", "flat"];
const INTERP_SAMPLING: &[&str] = &["center", "centroid", "sample", "first", "either"];

/// Parses `#[builtin]`, `#[location]` and `#[interpolate]` on a parameter or field.
pub(crate) fn io_attrs(attrs: &[Attribute], what: &str) -> Result<Option<(Io, Span)>> {
    let mut builtin: Option<(String, Span)> = None;
    let mut location: Option<(u32, Span)> = None;
    let mut interp: Option<((String, Option<String>), Span)> = None;
    let mut invariant: Option<Span> = None;
    for attr in attrs {
        if is_ignored(attr) {
            continue;
        }
        let span = attr.meta.span();
        if attr.path().is_ident("builtin") {
            let ident: syn::Ident = attr.parse_args().map_err(|_| {
                Error::new(
                    span,
                    "expected `#[builtin(name)]`, e.g. `#[builtin(position)]`",
                )
            })?;
            let name = ident.to_string();
            if !BUILTINS.iter().any(|(b, _)| *b == name) {
                let list: Vec<_> = BUILTINS.iter().map(|(b, _)| *b).collect();
                return Err(Error::new(
                    ident.span(),
                    format!(
                        "unknown builtin `{name}`; expected one of: {}",
                        list.join(", ")
                    ),
                ));
            }
            builtin = Some((name, ident.span()));
        } else if attr.path().is_ident("invariant") {
            if !matches!(attr.meta, syn::Meta::Path(_)) {
                return Err(Error::new(span, "`#[invariant]` takes no arguments"));
            }
            invariant = Some(span);
        } else if attr.path().is_ident("location") {
            let lit: LitInt = attr
                .parse_args()
                .map_err(|_| Error::new(span, "expected `#[location(N)]`"))?;
            location = Some((lit_u32(&lit)?, lit.span()));
        } else if attr.path().is_ident("interpolate") {
            let idents = attr
                .parse_args_with(
                    syn::punctuated::Punctuated::<syn::Ident, syn::Token![,]>::parse_terminated,
                )
                .map_err(|_| Error::new(span, "expected `#[interpolate(kind[, sampling])]`"))?;
            let names: Vec<String> = idents.iter().map(|i| i.to_string()).collect();
            let ok = !names.is_empty()
                && names.len() <= 2
                && INTERP_TYPES.contains(&names[0].as_str())
                && names
                    .get(1)
                    .is_none_or(|s| INTERP_SAMPLING.contains(&s.as_str()));
            if !ok {
                return Err(Error::new(
                    span,
                    "expected `#[interpolate(perspective|linear|flat[, center|centroid|sample|first|either])]`",
                ));
            }
            interp = Some(((names[0].clone(), names.get(1).cloned()), span));
        } else {
            return Err(unexpected(
                attr,
                what,
                "`#[builtin(..)]`, `#[location(N)]`, `#[interpolate(..)]`, `#[invariant]`",
            ));
        }
    }
    if let Some(s) = invariant {
        if builtin.as_ref().is_none_or(|(b, _)| b != "position") {
            return Err(Error::new(s, INVARIANT_MISPLACED));
        }
        return Ok(Some((Io::InvariantPosition, s)));
    }
    match (builtin, location, interp) {
        (Some(_), Some((_, s)), _) => Err(Error::new(
            s,
            "an input or output is either `#[builtin(..)]` or `#[location(..)]`, not both",
        )),
        (Some(_), None, Some((_, s))) => Err(Error::new(
            s,
            "`#[interpolate]` applies only to `#[location]` inputs and outputs",
        )),
        (Some((b, s)), None, None) => Ok(Some((Io::Builtin(b), s))),
        (None, Some((location, s)), interp) => Ok(Some((
            Io::Location {
                location,
                interpolate: interp.map(|i| i.0),
            },
            s,
        ))),
        (None, None, Some((_, s))) => Err(Error::new(s, "`#[interpolate]` needs a `#[location]`")),
        (None, None, None) => Ok(None),
    }
}
