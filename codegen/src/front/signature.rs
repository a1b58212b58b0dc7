//! Lowers function signatures: stage attributes, workgroup sizes, parameters with their IO
//! decorations, and return types with the entry point conventions.

use super::attrs::{self, StageAttr};
use super::ctx::{FnCtx, ModCtx};
use super::types::TyPos;
use crate::ir::{self, Expr, ExprKind, Io, Lit, Scalar, Stage, Ty};
use proc_macro2::Span;
use syn::spanned::Spanned;
use syn::{Error, Result};

pub(crate) fn lower_signature(m: &ModCtx, f: &syn::ItemFn) -> Result<(ir::Function, Vec<String>)> {
    let sig = &f.sig;
    if !sig.generics.params.is_empty() {
        return Err(Error::new(
            sig.generics.span(),
            "generic parameters are not supported; declare compile-time parameters as axes: `#[shader(axes(name: u32 = [..]))]`",
        ));
    }
    if let Some(t) = &sig.asyncness {
        return Err(Error::new(
            t.span,
            "`async` functions are not supported in shader code",
        ));
    }
    if let Some(t) = &sig.unsafety {
        return Err(Error::new(t.span, "`unsafe` is not needed in shader code"));
    }
    let stage_attr = attrs::fn_stage(&f.attrs)?;
    let mut cx = FnCtx::new(m, false);
    let stage = match stage_attr {
        None => None,
        Some(StageAttr::Vertex) => Some(Stage::Vertex),
        Some(StageAttr::Fragment) => Some(Stage::Fragment),
        Some(StageAttr::Compute(sizes, span)) => {
            let mut out = vec![];
            for s in &sizes {
                let e = cx.const_expr(s)?;
                if !matches!(e.ty, Ty::Scalar(s) if s.is_int32()) {
                    return Err(Error::new(
                        s.span(),
                        "workgroup sizes are integer constants (literals, consts or axes)",
                    ));
                }
                out.push(e);
            }
            while out.len() < 3 {
                out.push(Expr {
                    kind: ExprKind::Lit(Lit::Int(1, Scalar::AbstractInt)),
                    ty: Ty::Scalar(Scalar::AbstractInt),
                    span,
                });
            }
            #[expect(clippy::expect_used, reason = "three sizes were collected above")]
            let [x, y, z]: [Expr; 3] = out.try_into().expect("three sizes");
            Some(Stage::Compute(Box::new([x, y, z])))
        }
    };
    let when = match attrs::fn_when(&f.attrs)? {
        None => None,
        Some((_, span)) if stage.is_none() => {
            return Err(Error::new(
                span,
                "`#[when(..)]` on a function belongs on an entry point (`#[compute]`, `#[vertex]`, `#[fragment]`), which then exists only where it holds; a helper function is kept in every variant whose code calls it",
            ));
        }
        Some((e, _)) => {
            let p = cx.const_expr(&e)?;
            if p.ty != Ty::BOOL {
                return Err(Error::new(
                    e.span(),
                    "`#[when(..)]` takes a `bool` predicate over axes",
                ));
            }
            Some(p)
        }
    };
    let entry = stage.is_some();
    let mut params = vec![];
    let mut rust_names = vec![];
    for input in &sig.inputs {
        let syn::FnArg::Typed(pt) = input else {
            return Err(Error::new(
                input.span(),
                "`self` parameters are not supported; write free functions",
            ));
        };
        let (ident, mutable) = match &*pt.pat {
            syn::Pat::Ident(pi) if pi.by_ref.is_none() && pi.subpat.is_none() => {
                (&pi.ident, pi.mutability.is_some())
            }
            other => {
                return Err(Error::new(
                    other.span(),
                    "parameters must be plain names (`name: Type`)",
                ));
            }
        };
        let ty = cx.lower_type(&pt.ty, TyPos::Param)?;
        let io = attrs::io_attrs(&pt.attrs, "a parameter")?;
        if entry {
            if matches!(ty, Ty::Ptr(_)) {
                return Err(Error::new(
                    pt.ty.span(),
                    "entry point parameters cannot be references",
                ));
            }
            match &io {
                Some((io @ (Io::Builtin(_) | Io::InvariantPosition), s)) => {
                    check_builtin_type(&cx, io.builtin().unwrap_or_default(), &ty, *s)?
                }
                Some(_) if ty == Ty::U64 => {
                    return Err(Error::new(pt.ty.span(), super::build::U64_LOCATION));
                }
                Some(_) => {}
                None if matches!(ty, Ty::Struct(_)) => {}
                None => {
                    return Err(Error::new(
                        ident.span(),
                        "entry point parameters need `#[builtin(..)]` or `#[location(N)]`, or must be an IO struct",
                    ));
                }
            }
        } else if let Some((_, s)) = &io {
            return Err(Error::new(
                *s,
                "`#[builtin]`/`#[location]` belong on entry point parameters (`#[compute]`, `#[vertex]`, `#[fragment]` functions)",
            ));
        }
        if mutable && matches!(ty, Ty::Ptr(_)) {
            return Err(Error::new(
                ident.span(),
                "`mut` is not needed on `&mut` parameters",
            ));
        }
        let incoming = mutable.then(|| cx.fresh_name(&format!("{ident}_in")));
        let local = cx.declare(&ident.to_string(), ty, mutable, ident.span());
        rust_names.push(ident.to_string());
        params.push(ir::Param {
            local,
            io: io.map(|x| x.0),
            incoming,
        });
    }
    let ret = match &sig.output {
        syn::ReturnType::Default => Ty::Unit,
        syn::ReturnType::Type(_, t) => cx.lower_type(t, TyPos::Value)?,
    };
    let invariant = attrs::fn_invariant(&f.attrs);
    if let Some(span) = invariant
        && !(matches!(stage, Some(Stage::Vertex)) && ret == Ty::Vector(4, Scalar::F32))
    {
        return Err(Error::new(span, attrs::INVARIANT_MISPLACED));
    }
    let ret_io = match (&stage, &ret) {
        (Some(Stage::Compute(_)), r) if *r != Ty::Unit => {
            return Err(Error::new(
                sig.output.span(),
                "compute entry points return nothing",
            ));
        }
        (Some(Stage::Vertex), Ty::Vector(4, Scalar::F32)) if invariant.is_some() => {
            Some(Io::InvariantPosition)
        }
        (Some(Stage::Vertex), Ty::Vector(4, Scalar::F32)) => Some(Io::Builtin("position".into())),
        (Some(Stage::Vertex), Ty::Struct(_) | Ty::Unit) => None,
        (Some(Stage::Vertex), _) => {
            return Err(Error::new(
                sig.output.span(),
                "a vertex entry point returns `Vec4` (the position) or an IO struct",
            ));
        }
        (Some(Stage::Fragment), Ty::Struct(_) | Ty::Unit) => None,
        (Some(Stage::Fragment), Ty::Scalar(Scalar::U64)) => {
            return Err(Error::new(sig.output.span(), super::build::U64_LOCATION));
        }
        (Some(Stage::Fragment), r) if r.is_numeric() => Some(Io::Location {
            location: 0,
            interpolate: None,
        }),
        (Some(Stage::Fragment), _) => {
            return Err(Error::new(
                sig.output.span(),
                "a fragment entry point returns a vector/scalar (location 0) or an IO struct",
            ));
        }
        _ => None,
    };
    let func = ir::Function {
        name: sig.ident.to_string(),
        stage,
        when,
        params,
        ret,
        ret_io,
        locals: cx.locals,
        body: vec![],
        span: sig.ident.span(),
    };
    Ok((func, rust_names))
}

pub(crate) fn check_builtin_type(cx: &FnCtx<'_>, builtin: &str, ty: &Ty, span: Span) -> Result<()> {
    let expected = attrs::BUILTINS
        .iter()
        .find(|(b, _)| *b == builtin)
        .map(|b| b.1)
        .unwrap_or("?");
    let found = cx.ty_name(ty);
    if found != expected {
        return Err(Error::new(
            span,
            format!("`#[builtin({builtin})]` must have type `{expected}`, found `{found}`"),
        ));
    }
    Ok(())
}
