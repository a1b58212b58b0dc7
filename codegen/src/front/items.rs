//! Lowers module items: axes, structs, consts, statics (bindings) and function signatures,
//! then the function bodies. Checks that need the whole module live in `checks`.

use super::args::{BareStatic, ShaderArgs};
use super::attrs;
use super::ctx::{FnCtx, ModCtx, Mode, register};
use super::types::TyPos;
use crate::ir::{self, Expr, ExprKind, Lit, Scalar, Ty};
use syn::spanned::Spanned;
use syn::{Error, Result};

fn axis_value(e: &syn::Expr, ty: Scalar) -> Result<Lit> {
    let err = || {
        Error::new(
            e.span(),
            format!("axis values must be `{}` literals", ty.rust_name()),
        )
    };
    match (e, ty) {
        (syn::Expr::Lit(l), Scalar::Bool) => match &l.lit {
            syn::Lit::Bool(b) => Ok(Lit::Bool(b.value)),
            _ => Err(err()),
        },
        (syn::Expr::Lit(l), _) => match &l.lit {
            syn::Lit::Int(i) => Ok(Lit::Int(i.base10_parse::<u32>()?.into(), ty)),
            _ => Err(err()),
        },
        (syn::Expr::Unary(u), Scalar::I32) if matches!(u.op, syn::UnOp::Neg(_)) => {
            match axis_value(&u.expr, ty)? {
                Lit::Int(v, s) => Ok(Lit::Int(-v, s)),
                _ => Err(err()),
            }
        }
        _ => Err(err()),
    }
}

pub(crate) fn lower_axes(m: &mut ModCtx, args: &ShaderArgs) -> Result<()> {
    for a in &args.axes {
        let ty = match a.ty.to_string().as_str() {
            "u32" => Scalar::U32,
            "i32" => Scalar::I32,
            "bool" => Scalar::Bool,
            _ => {
                return Err(Error::new(
                    a.ty.span(),
                    "axis type must be `u32`, `i32` or `bool`",
                ));
            }
        };
        register(m, &a.name, "axis")?;
        let mut values = vec![];
        for v in &a.values {
            let lit = axis_value(v, ty)?;
            if values.contains(&lit) {
                return Err(Error::new(v.span(), "duplicate axis value"));
            }
            values.push(lit);
        }
        if values.is_empty() {
            return Err(Error::new(
                a.name.span(),
                "an axis needs at least one value",
            ));
        }
        let label = a
            .label
            .as_ref()
            .map_or_else(|| a.name.to_string(), |l| l.value());
        if label.is_empty() || !label.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(Error::new(
                a.label.span(),
                "axis labels are non-empty and alphanumeric",
            ));
        }
        let unnamed = match &a.unless {
            None => None,
            Some(_) if ty == Scalar::Bool => {
                return Err(Error::new(
                    a.unless.span(),
                    "`unless` names the value of a numeric axis that adds nothing to variant names; a `bool` axis adds its label only when `true` already",
                ));
            }
            Some(v) => {
                let lit = axis_value(v, ty)?;
                if !values.contains(&lit) {
                    return Err(Error::new(
                        v.span(),
                        "`unless` takes one of the axis' own values",
                    ));
                }
                Some(lit)
            }
        };
        m.module.axes.push(ir::Axis {
            name: a.name.to_string(),
            label,
            ty,
            values,
            unnamed,
            span: a.name.span(),
        });
    }
    Ok(())
}

pub(crate) fn lower_predicates(m: &mut ModCtx, args: &ShaderArgs) -> Result<()> {
    let mut excludes = vec![];
    let mut requires = None;
    {
        let mut cx = FnCtx::new(m, true);
        for e in &args.excludes {
            let p = cx.const_expr(e)?;
            if p.ty != Ty::BOOL {
                return Err(Error::new(
                    e.span(),
                    "`exclude(..)` takes a `bool` predicate over axes",
                ));
            }
            excludes.push(p);
        }
        for (name, pred) in &args.requires {
            if name != "subgroup" {
                return Err(Error::new(
                    name.span(),
                    "unknown capability; the DSL knows `subgroup`",
                ));
            }
            let p = match pred {
                Some(e) => cx.const_expr(e)?,
                None => Expr {
                    kind: ExprKind::Lit(Lit::Bool(true)),
                    ty: Ty::BOOL,
                    span: name.span(),
                },
            };
            if p.ty != Ty::BOOL {
                return Err(Error::new(
                    p.span,
                    "`requires(subgroup = ..)` takes a `bool` predicate over axes",
                ));
            }
            requires = Some(p);
        }
    }
    m.module.excludes = excludes;
    m.module.requires_subgroup = requires;
    Ok(())
}

fn unsupported_item(item: &syn::Item) -> Error {
    let (span, msg) = match item {
        syn::Item::Enum(e) => (
            e.ident.span(),
            "enums are not supported in shader modules; use `const` values",
        ),
        syn::Item::Impl(i) => (
            i.impl_token.span,
            "`impl` blocks are not supported; write free helper functions",
        ),
        syn::Item::Trait(t) => (t.ident.span(), "traits are not supported in shader modules"),
        syn::Item::Macro(m) => (
            m.mac.path.span(),
            "macros are not supported in shader modules",
        ),
        syn::Item::Mod(m) => (
            m.ident.span(),
            "nested modules are not supported in shader modules",
        ),
        other => (other.span(), "unsupported item in a shader module"),
    };
    Error::new(
        span,
        format!("{msg}; allowed items: `struct`, `const`, `static` bindings, `fn` and `use`"),
    )
}

/// Lowers the module's items, each tagged with the library it came from (`None`: the module
/// itself); with `Mode::Declarations`, stops before functions (used for the error stub, which
/// only needs the host-facing declarations).
pub(crate) fn lower_items(
    m: &mut ModCtx,
    items: &[(Option<String>, &syn::Item)],
    mode: Mode,
) -> Result<()> {
    let (mut structs, mut consts, mut statics, mut fns) = (vec![], vec![], vec![], vec![]);
    for (origin, item) in items {
        let origin = origin.clone();
        match item {
            syn::Item::Use(_) => {}
            syn::Item::Struct(s) => structs.push((origin, s)),
            syn::Item::Const(c) => consts.push((origin, c)),
            syn::Item::Static(_) | syn::Item::Verbatim(_) => {
                let tokens = quote::ToTokens::to_token_stream(*item);
                let parsed: BareStatic = syn::parse2(tokens).map_err(|_| unsupported_item(item))?;
                statics.push((origin, parsed));
            }
            syn::Item::Fn(f) => {
                if origin.is_some() || mode == Mode::Library {
                    no_entry_point(f)?;
                }
                fns.push((origin, f));
            }
            other => return Err(unsupported_item(other)),
        }
    }
    // 1. struct names, so any type can refer to any struct.
    for (origin, s) in &structs {
        m.origin = origin.clone();
        register(m, &s.ident, "struct")?;
        if !s.generics.params.is_empty() {
            return Err(Error::new(
                s.generics.span(),
                "generic structs are not supported; generics that are not axes are not allowed",
            ));
        }
        m.struct_ids
            .insert(s.ident.to_string(), m.module.structs.len());
        m.module.structs.push(ir::Struct {
            name: s.ident.to_string(),
            fields: vec![],
            span: s.ident.span(),
            uses: Default::default(),
        });
    }
    // 2. consts, in declaration order.
    for (origin, c) in &consts {
        m.origin = origin.clone();
        let lowered = {
            let mut cx = FnCtx::new(m, true);
            let ty = cx.lower_type(&c.ty, TyPos::Value)?;
            if !matches!(ty, Ty::Scalar(_) | Ty::Vector(..)) {
                return Err(Error::new(
                    c.ty.span(),
                    "constants must have a scalar or vector type",
                ));
            }
            let value = cx.const_expr(&c.expr)?;
            if !value.ty.converts_to(&ty) {
                return Err(Error::new(
                    c.expr.span(),
                    format!(
                        "mismatched types: expected `{}`, found `{}`",
                        cx.ty_name(&ty),
                        cx.ty_name(&value.ty)
                    ),
                ));
            }
            ir::Const {
                name: c.ident.to_string(),
                ty,
                value,
                span: c.ident.span(),
            }
        };
        register(m, &c.ident, "constant")?;
        m.const_ids
            .insert(lowered.name.clone(), m.module.consts.len());
        m.module.consts.push(lowered);
    }
    // 3. struct fields.
    for (id, (_, s)) in structs.iter().enumerate() {
        let syn::Fields::Named(named) = &s.fields else {
            return Err(Error::new(
                s.ident.span(),
                "shader structs need named fields",
            ));
        };
        let mut fields = vec![];
        {
            let mut cx = FnCtx::new(m, true);
            for f in &named.named {
                #[expect(clippy::expect_used, reason = "fields of `FieldsNamed` have names")]
                let ident = f.ident.as_ref().expect("named field");
                if naga::keywords::wgsl::RESERVED_SET.contains(&ident.to_string()) {
                    return Err(Error::new(
                        ident.span(),
                        "this field name is reserved in WGSL; rename it",
                    ));
                }
                let ty = cx.lower_type(&f.ty, TyPos::Field)?;
                let io = attrs::io_attrs(&f.attrs, "a struct field")?.map(|x| x.0);
                fields.push(ir::Field {
                    name: ident.to_string(),
                    ty,
                    io,
                    span: ident.span(),
                });
            }
        }
        if fields.is_empty() {
            return Err(Error::new(
                s.ident.span(),
                "shader structs need at least one field",
            ));
        }
        m.module.structs[id].fields = fields;
    }
    // 4. statics.
    for (origin, st) in &statics {
        m.origin = origin.clone();
        super::statics::lower_static(m, st)?;
    }
    if mode == Mode::Declarations {
        return Ok(());
    }
    // 5. function signatures.
    let mut rust_names = vec![];
    for (origin, f) in &fns {
        m.origin = origin.clone();
        register(m, &f.sig.ident, "function")?;
        let (func, names) = super::signature::lower_signature(m, f)?;
        m.fn_ids.insert(func.name.clone(), m.module.functions.len());
        m.module.functions.push(func);
        rust_names.push(names);
    }
    // 6. bodies.
    m.origin = None;
    for (i, (_, f)) in fns.iter().enumerate() {
        let (body, locals, calls) = {
            let mut cx = FnCtx::for_function(m, &m.module.functions[i], &rust_names[i]);
            let body = cx.fn_body(&f.block)?;
            (body, cx.locals, cx.calls)
        };
        let func = &mut m.module.functions[i];
        func.body = body;
        func.locals = locals;
        m.calls.push(calls);
    }
    Ok(())
}

/// Libraries hold helpers only: a stage attribute there is an error at the attribute.
fn no_entry_point(f: &syn::ItemFn) -> Result<()> {
    let stage = f.attrs.iter().find(|a| {
        ["vertex", "fragment", "compute"]
            .iter()
            .any(|s| a.path().is_ident(s))
    });
    match stage {
        None => Ok(()),
        Some(a) => Err(Error::new(
            a.meta.span(),
            "a library has no entry points: `#[vertex]`, `#[fragment]` and `#[compute]` functions belong in the `#[shader]` modules that use the library",
        )),
    }
}
