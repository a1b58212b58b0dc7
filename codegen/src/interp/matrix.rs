//! Matrices (`Mat2`–`Mat4`, column-major as in WGSL): a matrix value is a [`Value::Array`] of
//! its column vectors. Products follow WGSL: `m * v` sums the columns scaled by `v`'s
//! components, `v * m` dots `v` with each column, `a * b` is `a` times each column of `b`.

use super::{EvalError, Value, ops};
use crate::ir::{BinOp, Ty};

fn columns(v: &Value) -> Result<&[Value], EvalError> {
    match v {
        Value::Array(c) => Ok(c),
        v => Err(EvalError::Type(format!("a matrix expected, found {v}"))),
    }
}

fn vector(v: &Value) -> Result<&[Value], EvalError> {
    match v {
        Value::Vector(c) => Ok(c),
        v => Err(EvalError::Type(format!("a vector expected, found {v}"))),
    }
}

/// `m * v`: the sum of `m`'s columns, each scaled by `v`'s component.
fn times_vector(m: &Value, v: &Value) -> Result<Value, EvalError> {
    let mut sum: Option<Value> = None;
    for (column, x) in columns(m)?.iter().zip(vector(v)?) {
        let term = ops::binary(BinOp::Mul, column, x)?;
        sum = Some(match sum {
            None => term,
            Some(s) => ops::binary(BinOp::Add, &s, &term)?,
        });
    }
    sum.ok_or_else(|| EvalError::Type("an empty matrix".into()))
}

/// The dot product of two vectors, summed left to right.
fn dot(a: &Value, b: &Value) -> Result<Value, EvalError> {
    let products = ops::binary(BinOp::Mul, a, b)?;
    let mut terms = vector(&products)?.iter();
    let first = terms
        .next()
        .cloned()
        .ok_or_else(|| EvalError::Type("an empty vector".into()))?;
    terms.try_fold(first, |s, t| ops::binary(BinOp::Add, &s, t))
}

/// A binary operator with at least one matrix operand (`a_ty`, `b_ty` are the operand types).
pub(crate) fn binary(
    op: BinOp,
    a: &Value,
    b: &Value,
    a_ty: &Ty,
    b_ty: &Ty,
) -> Result<Value, EvalError> {
    let each = |m: &Value, f: &mut dyn FnMut(&Value) -> Result<Value, EvalError>| {
        columns(m)?
            .iter()
            .map(f)
            .collect::<Result<Vec<_>, _>>()
            .map(Value::Array)
    };
    match (op, a_ty, b_ty) {
        (BinOp::Mul, Ty::Matrix(..), Ty::Vector(..)) => times_vector(a, b),
        (BinOp::Mul, Ty::Vector(..), Ty::Matrix(..)) => columns(b)?
            .iter()
            .map(|c| dot(a, c))
            .collect::<Result<Vec<_>, _>>()
            .map(Value::Vector),
        (BinOp::Mul, Ty::Matrix(..), Ty::Matrix(..)) => each(b, &mut |c| times_vector(a, c)),
        (BinOp::Add | BinOp::Sub, Ty::Matrix(..), Ty::Matrix(..)) => columns(a)?
            .iter()
            .zip(columns(b)?)
            .map(|(x, y)| ops::binary(op, x, y))
            .collect::<Result<Vec<_>, _>>()
            .map(Value::Array),
        (BinOp::Mul, Ty::Matrix(..), Ty::Scalar(_)) => each(a, &mut |c| ops::binary(op, c, b)),
        (BinOp::Mul, Ty::Scalar(_), Ty::Matrix(..)) => each(b, &mut |c| ops::binary(op, a, c)),
        _ => Err(EvalError::Unsupported(format!(
            "the operator `{}` on {a_ty:?} and {b_ty:?}",
            op.symbol()
        ))),
    }
}

/// `-m`.
pub(crate) fn negate(m: &Value) -> Result<Value, EvalError> {
    columns(m)?
        .iter()
        .map(|c| ops::unary(crate::ir::UnOp::Neg, c))
        .collect::<Result<Vec<_>, _>>()
        .map(Value::Array)
}

/// `transpose(m)`.
pub(crate) fn transpose(m: &Value) -> Result<Value, EvalError> {
    let cols = columns(m)?;
    let rows = cols
        .first()
        .map(vector)
        .transpose()?
        .map_or(0, <[Value]>::len);
    (0..rows)
        .map(|r| {
            cols.iter()
                .map(|c| {
                    vector(c)?
                        .get(r)
                        .cloned()
                        .ok_or_else(|| EvalError::Type("a ragged matrix".into()))
                })
                .collect::<Result<Vec<_>, _>>()
                .map(Value::Vector)
        })
        .collect::<Result<Vec<_>, _>>()
        .map(Value::Array)
}

/// A matrix of `c` columns from its constructor's values: `c` column vectors, `c · r` scalars
/// in column order, or nothing (the zero matrix).
pub(crate) fn construct(c: u8, r: u8, args: Vec<Value>) -> Result<Value, EvalError> {
    let (c, r) = (usize::from(c), usize::from(r));
    if args.is_empty() {
        return Ok(Value::Array(vec![
            Value::Vector(vec![Value::F32(0.0); r]);
            c
        ]));
    }
    if args.len() == c && args.iter().all(|a| matches!(a, Value::Vector(_))) {
        return Ok(Value::Array(args));
    }
    if args.len() == c * r {
        return Ok(Value::Array(
            args.chunks(r)
                .map(|col| Value::Vector(col.to_vec()))
                .collect(),
        ));
    }
    Err(EvalError::Type(format!(
        "{} values for a {c}×{r} matrix",
        args.len()
    )))
}
