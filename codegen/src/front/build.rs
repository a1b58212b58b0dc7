//! Small constructors of typed IR expressions shared by every expression-lowering file, and
//! the messages for non-constant expressions and `u64` entry point IO. Imports nothing from the
//! front end.

use crate::ir::{Expr, ExprKind, Lit, Scalar, Ty};
use proc_macro2::Span;

pub(crate) fn mk(kind: ExprKind, ty: Ty, span: Span) -> Expr {
    Expr { kind, ty, span }
}

pub(crate) fn lit(l: Lit, span: Span) -> Expr {
    let ty = match l {
        Lit::Bool(_) => Ty::BOOL,
        Lit::Int(_, s) | Lit::Float(_, s) => Ty::Scalar(s),
    };
    mk(ExprKind::Lit(l), ty, span)
}

/// A literal `v` of scalar type `s`.
pub(crate) fn scalar_lit(s: Scalar, v: f64, span: Span) -> Expr {
    match s {
        Scalar::Bool => lit(Lit::Bool(v != 0.0), span),
        Scalar::F32 | Scalar::AbstractFloat => lit(Lit::Float(v, Scalar::F32), span),
        _ => lit(Lit::Int(v as i128, s), span),
    }
}

pub(crate) const NOT_CONST: &str = "not a constant expression: only literals, `const`s, axes, operators and casts are allowed here";

/// The error for a `u64` `#[location]` input or output.
pub(crate) const U64_LOCATION: &str = "`u64` cannot be a `#[location]` input or output: vertex attributes, inter-stage values and colour targets are 32-bit; pass two `u32`s (`x as u32` and `(x >> 32u32) as u32`)";
