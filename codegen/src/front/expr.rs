//! Expression lowering and typing: literals, paths, operators, casts, fields, swizzles,
//! indexing, constructors, struct literals and calls of module functions. Builtin functions
//! and methods are in `calls`.

use super::build::{NOT_CONST, lit, mk, scalar_lit};
use super::ctx::FnCtx;
use super::ops::bin_op;
use super::types::TyPos;
use crate::ir::{Expr, ExprKind, Lit, Scalar, Ty};
use syn::spanned::Spanned;
use syn::{Error, Result};

impl FnCtx<'_> {
    pub(crate) fn err_mismatch(&self, expected: &Ty, found: &Expr) -> Error {
        Error::new(
            found.span,
            format!(
                "mismatched types: expected `{}`, found `{}`",
                self.ty_name(expected),
                self.ty_name(&found.ty)
            ),
        )
    }

    /// Lowers `e` and checks it converts to `ty`.
    pub(crate) fn expr_as(&mut self, e: &syn::Expr, ty: &Ty) -> Result<Expr> {
        let x = self.expr(e)?;
        if !x.ty.converts_to(ty) {
            return Err(self.err_mismatch(ty, &x));
        }
        Ok(x)
    }

    pub(crate) fn expr(&mut self, e: &syn::Expr) -> Result<Expr> {
        let span = e.span();
        match e {
            syn::Expr::Lit(l) => lower_lit(&l.lit),
            syn::Expr::Paren(p) => self.expr(&p.expr),
            syn::Expr::Group(g) => self.expr(&g.expr),
            syn::Expr::Path(p) if p.qself.is_none() => match p.path.get_ident() {
                Some(id) => self.ident_expr(id),
                None => self.assoc_path(&p.path),
            },
            syn::Expr::Unary(u) => {
                let x = self.expr(&u.expr)?;
                self.unary(&u.op, x, span)
            }
            syn::Expr::Binary(b) => {
                let l = self.expr(&b.left)?;
                let r = self.expr(&b.right)?;
                let op = bin_op(&b.op).ok_or_else(|| {
                    Error::new(
                        b.op.span(),
                        "compound assignment is a statement, not an expression",
                    )
                })?;
                self.binary(op, l, r, b.op.span())
            }
            syn::Expr::Cast(c) => {
                let x = self.expr(&c.expr)?;
                let target = self.lower_type(&c.ty, TyPos::Value)?;
                let ok = matches!((&x.ty, &target), (Ty::Scalar(a), Ty::Scalar(b)) if *b != Scalar::Bool && a.is_numeric() || *a == Scalar::Bool && b.is_int());
                if !ok {
                    return Err(Error::new(
                        span,
                        format!(
                            "cannot cast `{}` as `{}`; `as` converts between `u32`, `i32`, `u64`, `f32` (and `bool` to integers); for vectors use `.as_vec3()`, `.as_uvec3()`, `.as_ivec3()`",
                            self.ty_name(&x.ty),
                            self.ty_name(&target)
                        ),
                    ));
                }
                Ok(mk(ExprKind::Cast(Box::new(x)), target, span))
            }
            syn::Expr::Field(f) => {
                let base = self.expr(&f.base)?;
                let syn::Member::Named(name) = &f.member else {
                    return Err(Error::new(
                        f.member.span(),
                        "tuple fields are not supported; use named struct fields",
                    ));
                };
                self.field(base, name)
            }
            syn::Expr::Index(i) => {
                if self.const_only {
                    return Err(Error::new(span, NOT_CONST));
                }
                let base = self.expr(&i.expr)?;
                let base = self.auto_deref(base);
                let index = self.expr(&i.index)?;
                if !matches!(index.ty, Ty::Scalar(s) if s.is_int32()) {
                    return Err(Error::new(
                        index.span,
                        format!(
                            "indices must be `u32` or `i32`, found `{}`",
                            self.ty_name(&index.ty)
                        ),
                    ));
                }
                let ty = match &base.ty {
                    Ty::Array(t, _) | Ty::RuntimeArray(t) => (**t).clone(),
                    Ty::Vector(_, s) => Ty::Scalar(*s),
                    Ty::Matrix(_, r) => Ty::Vector(*r, Scalar::F32),
                    other => {
                        return Err(Error::new(
                            i.expr.span(),
                            format!(
                                "cannot index into a value of type `{}`",
                                self.ty_name(other)
                            ),
                        ));
                    }
                };
                Ok(mk(
                    ExprKind::Index(Box::new(base), Box::new(index)),
                    ty,
                    span,
                ))
            }
            // Constant expressions allow vector/matrix constructors only (checked in `call`).
            syn::Expr::Call(c) => self.call(c),
            syn::Expr::MethodCall(mc) => {
                if self.const_only {
                    return Err(Error::new(span, NOT_CONST));
                }
                if let Some(t) = &mc.turbofish {
                    return Err(Error::new(t.span(), "generic arguments are not supported"));
                }
                let recv = self.expr(&mc.receiver)?;
                let args = mc
                    .args
                    .iter()
                    .map(|a| self.value_arg(a))
                    .collect::<Result<Vec<_>>>()?;
                self.method(recv, &mc.method, args, span)
            }
            syn::Expr::Struct(s) => self.struct_lit(s),
            syn::Expr::Array(a) => {
                let elems = a
                    .elems
                    .iter()
                    .map(|x| self.expr(x))
                    .collect::<Result<Vec<_>>>()?;
                let Some(first) = elems.first() else {
                    return Err(Error::new(span, "empty arrays are not supported"));
                };
                let mut ty = first.ty.clone();
                for x in &elems[1..] {
                    ty = ty.unify(&x.ty).ok_or_else(|| self.err_mismatch(&ty, x))?;
                }
                let len = lit(Lit::Int(elems.len() as i128, Scalar::AbstractInt), span);
                let ty = Ty::Array(
                    Box::new(ty.concretize()),
                    crate::ir::ArrayLen(Box::new(len)),
                );
                Ok(mk(ExprKind::Construct(elems), ty, span))
            }
            syn::Expr::Reference(_) => Err(Error::new(
                span,
                "references are only allowed as `&mut place` arguments of helper functions with `&mut T` parameters",
            )),
            syn::Expr::Closure(_) => Err(Error::new(
                span,
                "closures are not supported in shader code; write a helper `fn` in the module instead",
            )),
            syn::Expr::If(_) => Err(Error::new(
                span,
                "`if` is a statement in shader code, not a value; use `select(cond, if_true, if_false)` or assign to a `let mut`",
            )),
            syn::Expr::Macro(m) => Err(Error::new(
                m.mac.path.span(),
                "macros are not supported in shader code",
            )),
            syn::Expr::Tuple(_) => Err(Error::new(
                span,
                "tuples are not supported in shader code; use a struct or a vector",
            )),
            syn::Expr::Range(_) => Err(Error::new(
                span,
                "ranges are only allowed as the iterator of a `for` loop",
            )),
            syn::Expr::Match(_) => Err(Error::new(
                span,
                "`match` is not supported; use `if`/`else`",
            )),
            syn::Expr::Repeat(_) => Err(Error::new(
                span,
                "array repeat expressions are not supported; fill the array in a `for` loop",
            )),
            syn::Expr::Block(_)
            | syn::Expr::Loop(_)
            | syn::Expr::While(_)
            | syn::Expr::ForLoop(_)
            | syn::Expr::Unsafe(_) => Err(Error::new(
                span,
                "blocks and loops are statements in shader code, not values",
            )),
            _ => Err(Error::new(
                span,
                "unsupported expression in shader code; see the language guide for the accepted subset",
            )),
        }
    }

    /// A method or builtin argument: `&mut` is not allowed there.
    pub(crate) fn value_arg(&mut self, a: &syn::Expr) -> Result<Expr> {
        self.expr(a)
    }

    fn ident_expr(&mut self, id: &syn::Ident) -> Result<Expr> {
        let name = id.to_string();
        let span = id.span();
        if !self.const_only
            && let Some(l) = self.lookup_local(&name)
        {
            return Ok(mk(ExprKind::Local(l), self.locals[l].ty.clone(), span));
        }
        let m = &self.m.module;
        if let Some(a) = m.axis(&name) {
            return Ok(mk(ExprKind::Axis(a), Ty::Scalar(m.axes[a].ty), span));
        }
        if let Some(&c) = self.m.const_ids.get(&name) {
            return Ok(mk(ExprKind::Const(c), m.consts[c].ty.clone(), span));
        }
        if let Some(&g) = self.m.global_ids.get(&name) {
            if self.const_only {
                return Err(Error::new(
                    span,
                    format!("`{name}` is a binding, not a constant; {NOT_CONST}"),
                ));
            }
            return Ok(mk(ExprKind::Global(g), m.globals[g].ty.clone(), span));
        }
        let msg = if self.m.struct_ids.contains_key(&name) {
            format!("`{name}` is a struct; construct it with `{name} {{ field: value, .. }}`")
        } else if self.m.fn_ids.contains_key(&name) {
            format!("`{name}` is a function; call it, function values are not supported")
        } else {
            format!(
                "cannot find value `{name}` in this shader module (locals, parameters, consts, statics and axes are in scope)"
            )
        };
        Err(Error::new(span, msg))
    }

    fn assoc_path(&mut self, path: &syn::Path) -> Result<Expr> {
        let segs: Vec<String> = path.segments.iter().map(|s| s.ident.to_string()).collect();
        let span = path.span();
        let last = segs.last().map(String::as_str).unwrap_or_default();
        let owner = segs
            .get(segs.len().wrapping_sub(2))
            .map(String::as_str)
            .unwrap_or_default();
        if segs.iter().any(|s| s == "f32") && owner == "consts" {
            let v = match last {
                "PI" => std::f64::consts::PI,
                "TAU" => std::f64::consts::TAU,
                "E" => std::f64::consts::E,
                "FRAC_PI_2" => std::f64::consts::FRAC_PI_2,
                "FRAC_PI_4" => std::f64::consts::FRAC_PI_4,
                "FRAC_1_PI" => std::f64::consts::FRAC_1_PI,
                "SQRT_2" => std::f64::consts::SQRT_2,
                "LN_2" => std::f64::consts::LN_2,
                _ => return Err(Error::new(span, "unknown `f32` constant")),
            };
            return Ok(lit(Lit::Float((v as f32) as f64, Scalar::F32), span));
        }
        match (owner, last) {
            ("u32", "MAX") => return Ok(lit(Lit::Int(u32::MAX.into(), Scalar::U32), span)),
            ("u32", "MIN") => return Ok(lit(Lit::Int(0, Scalar::U32), span)),
            ("u64", "MAX") => return Ok(lit(Lit::Int(u64::MAX.into(), Scalar::U64), span)),
            ("u64", "MIN") => return Ok(lit(Lit::Int(0, Scalar::U64), span)),
            ("i32", "MAX") => return Ok(lit(Lit::Int(i32::MAX.into(), Scalar::I32), span)),
            ("i32", "MIN") => return Ok(lit(Lit::Int(i32::MIN.into(), Scalar::I32), span)),
            ("f32", "MAX") => return Ok(lit(Lit::Float(f32::MAX as f64, Scalar::F32), span)),
            ("f32", "MIN") => return Ok(lit(Lit::Float(f32::MIN as f64, Scalar::F32), span)),
            ("f32", "EPSILON") => {
                return Ok(lit(Lit::Float(f32::EPSILON as f64, Scalar::F32), span));
            }
            _ => {}
        }
        if let Some(ty) = super::types::vec_or_mat_named(owner) {
            #[expect(
                clippy::expect_used,
                reason = "vec_or_mat_named gives vectors and matrices, which have a scalar"
            )]
            let s = ty.scalar().expect("vector or matrix");
            let n = match ty {
                Ty::Vector(n, _) => n as usize,
                _ => 0,
            };
            let unit = |i: usize| -> Result<Expr> {
                if i >= n {
                    return Err(Error::new(span, format!("`{owner}` has no axis `{last}`")));
                }
                let args = (0..n)
                    .map(|k| scalar_lit(s, if k == i { 1.0 } else { 0.0 }, span))
                    .collect();
                Ok(mk(ExprKind::Construct(args), ty.clone(), span))
            };
            return match (last, &ty) {
                ("ZERO", _) => Ok(mk(ExprKind::Construct(vec![]), ty.clone(), span)),
                ("ONE", Ty::Vector(..)) => Ok(mk(
                    ExprKind::Construct(vec![scalar_lit(s, 1.0, span)]),
                    ty.clone(),
                    span,
                )),
                ("NEG_ONE", Ty::Vector(..)) => Ok(mk(
                    ExprKind::Construct(vec![scalar_lit(s, -1.0, span)]),
                    ty.clone(),
                    span,
                )),
                ("X", Ty::Vector(..)) => unit(0),
                ("Y", Ty::Vector(..)) => unit(1),
                ("Z", Ty::Vector(..)) => unit(2),
                ("W", Ty::Vector(..)) => unit(3),
                ("IDENTITY", Ty::Matrix(c, r)) => {
                    let args = (0..*c)
                        .flat_map(|i| (0..*r).map(move |j| (i, j)))
                        .map(|(i, j)| scalar_lit(Scalar::F32, if i == j { 1.0 } else { 0.0 }, span))
                        .collect();
                    Ok(mk(ExprKind::Construct(args), ty.clone(), span))
                }
                _ => Err(Error::new(
                    span,
                    format!(
                        "unknown associated constant `{owner}::{last}`; expected ZERO, ONE, NEG_ONE, X, Y, Z, W or (matrices) IDENTITY"
                    ),
                )),
            };
        }
        Err(Error::new(
            span,
            format!("cannot resolve path `{}` in shader code", segs.join("::")),
        ))
    }

    /// `*p` for pointer-typed expressions, so fields and indices work through `&mut` params.
    pub(crate) fn auto_deref(&self, e: Expr) -> Expr {
        match e.ty.clone() {
            Ty::Ptr(t) => {
                let span = e.span;
                mk(ExprKind::Deref(Box::new(e)), *t, span)
            }
            _ => e,
        }
    }

    fn field(&mut self, base: Expr, name: &syn::Ident) -> Result<Expr> {
        let base = self.auto_deref(base);
        let n = name.to_string();
        let span = name.span();
        match &base.ty {
            Ty::Struct(id) => {
                let s = &self.m.module.structs[*id];
                let Some(i) = s.fields.iter().position(|f| f.name == n) else {
                    let names: Vec<_> = s.fields.iter().map(|f| f.name.as_str()).collect();
                    return Err(Error::new(
                        span,
                        format!(
                            "no field `{n}` on struct `{}`; its fields are: {}",
                            s.name,
                            names.join(", ")
                        ),
                    ));
                };
                let ty = s.fields[i].ty.clone();
                Ok(mk(ExprKind::Field(Box::new(base), i), ty, span))
            }
            Ty::Vector(size, s) => {
                let idx = ["x", "y", "z", "w"].iter().position(|c| *c == n);
                match idx {
                    Some(i) if i < *size as usize => {
                        let ty = Ty::Scalar(*s);
                        Ok(mk(ExprKind::Swizzle(Box::new(base), n), ty, span))
                    }
                    _ => Err(Error::new(
                        span,
                        format!(
                            "no field `{n}` on `{}`; use `.x`..`.w` or swizzle methods like `.xy()`",
                            self.ty_name(&base.ty)
                        ),
                    )),
                }
            }
            Ty::Matrix(c, r) => {
                let idx = ["x_axis", "y_axis", "z_axis", "w_axis"]
                    .iter()
                    .position(|c| *c == n);
                match idx {
                    Some(i) if i < *c as usize => {
                        let ty = Ty::Vector(*r, Scalar::F32);
                        let index = lit(Lit::Int(i as i128, Scalar::U32), span);
                        Ok(mk(
                            ExprKind::Index(Box::new(base), Box::new(index)),
                            ty,
                            span,
                        ))
                    }
                    _ => Err(Error::new(
                        span,
                        format!("no field `{n}` on a matrix; use `.x_axis`.. or `.col(i)`"),
                    )),
                }
            }
            other => Err(Error::new(
                span,
                format!(
                    "no field `{n}` on a value of type `{}`",
                    self.ty_name(other)
                ),
            )),
        }
    }
}

fn lower_lit(l: &syn::Lit) -> Result<Expr> {
    let span = l.span();
    match l {
        syn::Lit::Bool(b) => Ok(lit(Lit::Bool(b.value), span)),
        syn::Lit::Int(i) => {
            let s = match i.suffix() {
                "" => Scalar::AbstractInt,
                "u32" => Scalar::U32,
                "i32" => Scalar::I32,
                "u64" => Scalar::U64,
                "f32" => Scalar::F32,
                other => {
                    return Err(Error::new(
                        span,
                        format!(
                            "`{other}` literals are not GPU types; use `u32`, `i32`, `u64` or `f32`"
                        ),
                    ));
                }
            };
            let v: u64 = i.base10_parse()?;
            if s == Scalar::U64 {
                return Ok(lit(Lit::Int(v.into(), s), span));
            }
            let max = match s {
                Scalar::I32 => i32::MAX as u64 + 1,
                _ => u32::MAX as u64,
            };
            if v > max {
                let hint = if s == Scalar::AbstractInt {
                    "; write a `u64` suffix for a 64-bit value"
                } else {
                    ""
                };
                return Err(Error::new(
                    span,
                    format!("integer literal out of range for 32 bits{hint}"),
                ));
            }
            if s == Scalar::F32 {
                return Ok(lit(Lit::Float(v as f64, s), span));
            }
            Ok(lit(Lit::Int(v.into(), s), span))
        }
        syn::Lit::Float(f) => {
            let s = match f.suffix() {
                "" => Scalar::AbstractFloat,
                "f32" => Scalar::F32,
                other => {
                    return Err(Error::new(
                        span,
                        format!("`{other}` literals are not supported; use `f32`"),
                    ));
                }
            };
            Ok(lit(Lit::Float(f.base10_parse()?, s), span))
        }
        _ => Err(Error::new(
            span,
            "only numeric and boolean literals are supported in shader code",
        )),
    }
}
