//! Operators: typing of unary and binary operators (scalar, vector, vector-scalar and matrix
//! arithmetic, bit operations, logic and comparisons) and the syn operator mapping.

use super::build::{NOT_CONST, mk};
use super::ctx::FnCtx;
use crate::ir::{BinOp, Expr, ExprKind, Scalar, Ty, UnOp};
use proc_macro2::Span;
use syn::{Error, Result};

impl FnCtx<'_> {
    pub(crate) fn unary(&mut self, op: &syn::UnOp, x: Expr, span: Span) -> Result<Expr> {
        match op {
            syn::UnOp::Neg(_) => {
                if !x.ty.is_numeric() && !matches!(x.ty, Ty::Matrix(..))
                    || matches!(x.ty.scalar(), Some(Scalar::U32 | Scalar::U64))
                {
                    return Err(Error::new(
                        span,
                        format!("cannot negate a value of type `{}`", self.ty_name(&x.ty)),
                    ));
                }
                let ty = x.ty.clone();
                Ok(mk(ExprKind::Unary(UnOp::Neg, Box::new(x)), ty, span))
            }
            syn::UnOp::Not(_) => {
                let op = match x.ty.scalar() {
                    Some(Scalar::Bool) => UnOp::Not,
                    Some(s) if s.is_int() && !matches!(x.ty, Ty::Matrix(..)) => UnOp::BitNot,
                    _ => {
                        return Err(Error::new(
                            span,
                            format!(
                                "cannot apply `!` to a value of type `{}`",
                                self.ty_name(&x.ty)
                            ),
                        ));
                    }
                };
                let ty = x.ty.clone();
                Ok(mk(ExprKind::Unary(op, Box::new(x)), ty, span))
            }
            syn::UnOp::Deref(_) => match x.ty.clone() {
                Ty::Ptr(t) => Ok(mk(ExprKind::Deref(Box::new(x)), *t, span)),
                other => Err(Error::new(
                    span,
                    format!(
                        "only `&mut` parameters can be dereferenced; this has type `{}`",
                        self.ty_name(&other)
                    ),
                )),
            },
            _ => Err(Error::new(span, "unsupported unary operator")),
        }
    }

    pub(crate) fn binary(&mut self, op: BinOp, l: Expr, r: Expr, span: Span) -> Result<Expr> {
        use BinOp::*;
        let mut msg = format!(
            "cannot apply `{}` to `{}` and `{}`",
            op.symbol(),
            self.ty_name(&l.ty),
            self.ty_name(&r.ty)
        );
        let mixed = [l.ty.scalar(), r.ty.scalar()];
        if mixed.contains(&Some(Scalar::U64)) && mixed.iter().flatten().any(|s| *s != Scalar::U64) {
            msg.push_str("; convert the other side with `as u64` (or the `u64` one with `as u32`, which keeps its low 32 bits)");
        } else if mixed.contains(&Some(Scalar::I32)) && mixed.contains(&Some(Scalar::U32)) {
            msg.push_str("; convert one side with `as`, and note that a `let` of an unsuffixed integer literal is `i32` (write `0u32` for a `u32`)");
        } else if mixed.iter().flatten().any(|s| s.is_float())
            && mixed.iter().flatten().any(|s| s.is_int())
        {
            msg.push_str("; convert with `as f32` (or `as u32`/`as i32`)");
        }
        let fail = |_: &Self| Error::new(span, msg.clone());
        let mut r = r;
        let ty = match op {
            And | Or => match l.ty.unify(&r.ty) {
                Some(Ty::Scalar(Scalar::Bool)) => Ty::BOOL,
                _ => return Err(fail(self)),
            },
            Eq | Ne | Lt | Le | Gt | Ge => match (&l.ty, &r.ty) {
                (Ty::Scalar(a), Ty::Scalar(b))
                    if a.unify(*b).is_some() && (matches!(op, Eq | Ne) || a.is_numeric()) =>
                {
                    Ty::BOOL
                }
                (Ty::Vector(..), Ty::Vector(..)) => {
                    return Err(Error::new(
                        span,
                        "comparing vectors is not supported; compare components, e.g. `a.x < b.x`",
                    ));
                }
                _ => return Err(fail(self)),
            },
            Shl | Shr => {
                if !l.ty.is_int_like() || !r.ty.is_int_like() {
                    return Err(fail(self));
                }
                if r.ty.scalar() == Some(Scalar::U64) {
                    return Err(Error::new(
                        r.span,
                        "shift amounts are `u32` (also for a `u64` value); convert with `as u32`",
                    ));
                }
                if r.ty.scalar() == Some(Scalar::I32) {
                    let ty = match r.ty {
                        Ty::Vector(n, _) => Ty::Vector(n, Scalar::U32),
                        _ => Ty::U32,
                    };
                    let s = r.span;
                    r = mk(ExprKind::Cast(Box::new(r)), ty, s);
                }
                l.ty.clone()
            }
            BitAnd | BitOr | BitXor => match l.ty.unify(&r.ty) {
                Some(t) if t.is_int_like() || t == Ty::BOOL => t,
                _ => return Err(fail(self)),
            },
            Add | Sub | Mul | Div | Rem => match (&l.ty, &r.ty) {
                (a, b) if a.is_numeric() && b.is_numeric() => match a.unify(b) {
                    Some(t) => t,
                    None => match (a, b) {
                        (Ty::Vector(n, s), Ty::Scalar(t)) | (Ty::Scalar(t), Ty::Vector(n, s)) => {
                            Ty::Vector(*n, s.unify(*t).ok_or_else(|| fail(self))?)
                        }
                        _ => return Err(fail(self)),
                    },
                },
                (Ty::Matrix(c, r1), Ty::Vector(n, s)) if op == Mul && c == n && s.is_float() => {
                    Ty::Vector(*r1, Scalar::F32)
                }
                (Ty::Vector(n, s), Ty::Matrix(c, r1)) if op == Mul && r1 == n && s.is_float() => {
                    Ty::Vector(*c, Scalar::F32)
                }
                (Ty::Matrix(a, b), Ty::Matrix(c, d)) if op == Mul && a == d => Ty::Matrix(*c, *b),
                (Ty::Matrix(a, b), Ty::Matrix(c, d))
                    if matches!(op, Add | Sub) && a == c && b == d =>
                {
                    l.ty.clone()
                }
                (Ty::Matrix(..), Ty::Scalar(s)) | (Ty::Scalar(s), Ty::Matrix(..))
                    if op == Mul && s.is_float() =>
                {
                    if matches!(l.ty, Ty::Matrix(..)) {
                        l.ty.clone()
                    } else {
                        r.ty.clone()
                    }
                }
                _ => return Err(fail(self)),
            },
        };
        // WGSL has no `^` on `bool` or `vecN<bool>` (naga rejects it); on booleans it is `!=`.
        let op = if op == BitXor && ty.scalar() == Some(Scalar::Bool) {
            Ne
        } else {
            op
        };
        if self.const_only && !matches!(ty, Ty::Scalar(_)) {
            return Err(Error::new(span, NOT_CONST));
        }
        Ok(mk(ExprKind::Binary(op, Box::new(l), Box::new(r)), ty, span))
    }
}

pub(crate) fn bin_op(op: &syn::BinOp) -> Option<BinOp> {
    use syn::BinOp as B;
    Some(match op {
        B::Add(_) => BinOp::Add,
        B::Sub(_) => BinOp::Sub,
        B::Mul(_) => BinOp::Mul,
        B::Div(_) => BinOp::Div,
        B::Rem(_) => BinOp::Rem,
        B::And(_) => BinOp::And,
        B::Or(_) => BinOp::Or,
        B::BitXor(_) => BinOp::BitXor,
        B::BitAnd(_) => BinOp::BitAnd,
        B::BitOr(_) => BinOp::BitOr,
        B::Shl(_) => BinOp::Shl,
        B::Shr(_) => BinOp::Shr,
        B::Eq(_) => BinOp::Eq,
        B::Lt(_) => BinOp::Lt,
        B::Le(_) => BinOp::Le,
        B::Ne(_) => BinOp::Ne,
        B::Ge(_) => BinOp::Ge,
        B::Gt(_) => BinOp::Gt,
        _ => return None,
    })
}

/// The operator of a compound assignment (`+=` gives `Add`).
pub(crate) fn compound_op(op: &syn::BinOp) -> Option<BinOp> {
    use syn::BinOp as B;
    Some(match op {
        B::AddAssign(_) => BinOp::Add,
        B::SubAssign(_) => BinOp::Sub,
        B::MulAssign(_) => BinOp::Mul,
        B::DivAssign(_) => BinOp::Div,
        B::RemAssign(_) => BinOp::Rem,
        B::BitXorAssign(_) => BinOp::BitXor,
        B::BitAndAssign(_) => BinOp::BitAnd,
        B::BitOrAssign(_) => BinOp::BitOr,
        B::ShlAssign(_) => BinOp::Shl,
        B::ShrAssign(_) => BinOp::Shr,
        _ => return None,
    })
}
