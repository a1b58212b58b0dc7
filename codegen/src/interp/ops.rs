//! Operators and conversions with WGSL's runtime semantics (the DSL's documented semantics,
//! see the guide's "Semantics" section):
//!
//! - `i32`/`u32`/`u64` `+ - *` and unary `-` wrap (two's complement);
//! - shifts use only the low 5 bits of the amount (`x << 33` is `x << 1`), 6 on `u64`, `>>`
//!   is arithmetic on `i32` and logical on `u32` and `u64`;
//! - integer `x / 0` is `x`, `x % 0` is `0`, `i32::MIN / -1` is `i32::MIN` and
//!   `i32::MIN % -1` is `0`; `%` truncates (its sign is the dividend's);
//! - float `%` is `x - y * trunc(x / y)`;
//! - `f32 as i32`/`as u32` saturate to the range (truncating toward zero); NaN gives 0;
//! - `i32 as u32` and `u32 as i32` keep the bits; `bool as` integer is 0 or 1;
//! - `u64 as u32`/`as i32` keep the low 32 bits, `u32 as u64` zero-extends and `i32 as u64`
//!   sign-extends (as Rust does); `f32 as u64` saturates like `as u32`, to the largest `f32`
//!   below 2^64.

use super::error::{EvalError, type_err};
use super::value::Value;
use crate::ir::{BinOp, Scalar, UnOp};

/// Applies `f` to each component of a scalar or vector.
pub(crate) fn map1(
    v: &Value,
    f: &mut impl FnMut(&Value) -> Result<Value, EvalError>,
) -> Result<Value, EvalError> {
    match v {
        Value::Vector(c) => Ok(Value::Vector(c.iter().map(f).collect::<Result<_, _>>()?)),
        s => f(s),
    }
}

/// Applies `f` componentwise to two operands; a scalar operand is splat to the other's width.
pub(crate) fn map2(
    a: &Value,
    b: &Value,
    f: &mut impl FnMut(&Value, &Value) -> Result<Value, EvalError>,
) -> Result<Value, EvalError> {
    match (a, b) {
        (Value::Vector(x), Value::Vector(y)) if x.len() == y.len() => Ok(Value::Vector(
            x.iter()
                .zip(y)
                .map(|(p, q)| f(p, q))
                .collect::<Result<_, _>>()?,
        )),
        (Value::Vector(x), s) => Ok(Value::Vector(
            x.iter().map(|p| f(p, s)).collect::<Result<_, _>>()?,
        )),
        (s, Value::Vector(y)) => Ok(Value::Vector(
            y.iter().map(|q| f(s, q)).collect::<Result<_, _>>()?,
        )),
        (p, q) => f(p, q),
    }
}

/// Applies `f` componentwise to three operands (scalars splat).
pub(crate) fn map3(
    a: &Value,
    b: &Value,
    c: &Value,
    f: &mut impl FnMut(&Value, &Value, &Value) -> Result<Value, EvalError>,
) -> Result<Value, EvalError> {
    let n = [a, b, c]
        .iter()
        .find_map(|v| match v {
            Value::Vector(c) => Some(c.len()),
            _ => None,
        })
        .unwrap_or(0);
    if n == 0 {
        return f(a, b, c);
    }
    let at = |v: &Value, i: usize| match v {
        Value::Vector(c) => c.get(i).cloned(),
        s => Some(s.clone()),
    };
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let (Some(x), Some(y), Some(z)) = (at(a, i), at(b, i), at(c, i)) else {
            return type_err("vector operands of different widths");
        };
        out.push(f(&x, &y, &z)?);
    }
    Ok(Value::Vector(out))
}

/// A unary operator.
pub fn unary(op: UnOp, v: &Value) -> Result<Value, EvalError> {
    map1(v, &mut |x| {
        Ok(match (op, x) {
            (UnOp::Neg, Value::I32(i)) => Value::I32(i.wrapping_neg()),
            (UnOp::Neg, Value::F32(f)) => Value::F32(-f),
            (UnOp::Not, Value::Bool(b)) => Value::Bool(!b),
            (UnOp::BitNot, Value::I32(i)) => Value::I32(!i),
            (UnOp::BitNot, Value::U32(u)) => Value::U32(!u),
            (UnOp::BitNot, Value::U64(u)) => Value::U64(!u),
            _ => return type_err(format!("{op:?} of {x}")),
        })
    })
}

/// A binary operator. `&&`/`||` here are the strict forms; [`super::eval_expr`] short-circuits.
pub fn binary(op: BinOp, a: &Value, b: &Value) -> Result<Value, EvalError> {
    map2(a, b, &mut |x, y| scalar_binary(op, x, y))
}

fn scalar_binary(op: BinOp, a: &Value, b: &Value) -> Result<Value, EvalError> {
    use BinOp::*;
    if matches!(op, Shl | Shr) {
        let Value::U32(s) = b else {
            return type_err(format!("shift amount {b}"));
        };
        let (s, s64) = (s & 31, s & 63);
        return Ok(match (op, a) {
            (Shl, Value::I32(x)) => Value::I32(x.wrapping_shl(s)),
            (Shl, Value::U32(x)) => Value::U32(x.wrapping_shl(s)),
            (Shl, Value::U64(x)) => Value::U64(x.wrapping_shl(s64)),
            (Shr, Value::I32(x)) => Value::I32(x >> s),
            (Shr, Value::U32(x)) => Value::U32(x >> s),
            (Shr, Value::U64(x)) => Value::U64(x >> s64),
            _ => return type_err(format!("shift of {a}")),
        });
    }
    Ok(match (a, b) {
        (Value::Bool(x), Value::Bool(y)) => Value::Bool(match op {
            And | BitAnd => *x && *y,
            Or | BitOr => *x || *y,
            BitXor | Ne => x != y,
            Eq => x == y,
            _ => return type_err(format!("{op:?} on bool")),
        }),
        (Value::I32(x), Value::I32(y)) => {
            let (x, y) = (*x, *y);
            match op {
                Add => Value::I32(x.wrapping_add(y)),
                Sub => Value::I32(x.wrapping_sub(y)),
                Mul => Value::I32(x.wrapping_mul(y)),
                // x / 0 = x; MIN / -1 = MIN (wrapping_div gives MIN).
                Div if y == 0 => Value::I32(x),
                Div => Value::I32(x.wrapping_div(y)),
                // x % 0 = 0; MIN % -1 = 0 (wrapping_rem gives 0).
                Rem if y == 0 => Value::I32(0),
                Rem => Value::I32(x.wrapping_rem(y)),
                BitAnd => Value::I32(x & y),
                BitOr => Value::I32(x | y),
                BitXor => Value::I32(x ^ y),
                _ => compare(op, x.cmp(&y))?,
            }
        }
        (Value::U32(x), Value::U32(y)) => {
            let (x, y) = (*x, *y);
            match op {
                Add => Value::U32(x.wrapping_add(y)),
                Sub => Value::U32(x.wrapping_sub(y)),
                Mul => Value::U32(x.wrapping_mul(y)),
                Div if y == 0 => Value::U32(x),
                Div => Value::U32(x / y),
                Rem if y == 0 => Value::U32(0),
                Rem => Value::U32(x % y),
                BitAnd => Value::U32(x & y),
                BitOr => Value::U32(x | y),
                BitXor => Value::U32(x ^ y),
                _ => compare(op, x.cmp(&y))?,
            }
        }
        (Value::U64(x), Value::U64(y)) => {
            let (x, y) = (*x, *y);
            match op {
                Add => Value::U64(x.wrapping_add(y)),
                Sub => Value::U64(x.wrapping_sub(y)),
                Mul => Value::U64(x.wrapping_mul(y)),
                Div if y == 0 => Value::U64(x),
                Div => Value::U64(x / y),
                Rem if y == 0 => Value::U64(0),
                Rem => Value::U64(x % y),
                BitAnd => Value::U64(x & y),
                BitOr => Value::U64(x | y),
                BitXor => Value::U64(x ^ y),
                _ => compare(op, x.cmp(&y))?,
            }
        }
        (Value::F32(x), Value::F32(y)) => {
            let (x, y) = (*x, *y);
            match op {
                Add => Value::F32(x + y),
                Sub => Value::F32(x - y),
                Mul => Value::F32(x * y),
                Div => Value::F32(x / y),
                Rem => Value::F32(x - y * (x / y).trunc()),
                Eq => Value::Bool(x == y),
                Ne => Value::Bool(x != y),
                Lt => Value::Bool(x < y),
                Le => Value::Bool(x <= y),
                Gt => Value::Bool(x > y),
                Ge => Value::Bool(x >= y),
                _ => return type_err(format!("{op:?} on f32")),
            }
        }
        _ => return type_err(format!("{op:?} of {a} and {b}")),
    })
}

fn compare(op: BinOp, o: std::cmp::Ordering) -> Result<Value, EvalError> {
    use std::cmp::Ordering::*;
    Ok(Value::Bool(match op {
        BinOp::Eq => o == Equal,
        BinOp::Ne => o != Equal,
        BinOp::Lt => o == Less,
        BinOp::Le => o != Greater,
        BinOp::Gt => o == Greater,
        BinOp::Ge => o != Less,
        _ => return type_err(format!("{op:?} on integers")),
    }))
}

/// The largest `f32` not above `i32::MAX` (2147483520): WGSL's saturation bound.
const I32_MAX_F: f32 = 2_147_483_520.0;
/// The largest `f32` not above `u32::MAX` (4294967040).
const U32_MAX_F: f32 = 4_294_967_040.0;
/// The largest `f32` not above `u64::MAX` (2^64 - 2^40).
const U64_MAX_F: f32 = 18_446_742_974_197_923_840.0;

/// `v as T` (componentwise for vectors) with WGSL's value conversions.
pub fn cast(v: &Value, to: Scalar) -> Result<Value, EvalError> {
    let to = to.concretize();
    map1(v, &mut |x| {
        Ok(match (x, to) {
            (x, t) if x.scalar() == Some(t) => x.clone(),
            (Value::Bool(b), Scalar::I32) => Value::I32(*b as i32),
            (Value::Bool(b), Scalar::U32) => Value::U32(*b as u32),
            (Value::Bool(b), Scalar::F32) => Value::F32(*b as u8 as f32),
            (Value::I32(i), Scalar::U32) => Value::U32(*i as u32),
            (Value::I32(i), Scalar::F32) => Value::F32(*i as f32),
            (Value::I32(i), Scalar::Bool) => Value::Bool(*i != 0),
            (Value::U32(u), Scalar::I32) => Value::I32(*u as i32),
            (Value::U32(u), Scalar::F32) => Value::F32(*u as f32),
            (Value::U32(u), Scalar::Bool) => Value::Bool(*u != 0),
            (Value::Bool(b), Scalar::U64) => Value::U64((*b).into()),
            (Value::I32(i), Scalar::U64) => Value::U64(*i as u64),
            (Value::U32(u), Scalar::U64) => Value::U64((*u).into()),
            (Value::F32(f), Scalar::U64) => Value::U64(f.clamp(0.0, U64_MAX_F) as u64),
            (Value::U64(u), Scalar::U32) => Value::U32(*u as u32),
            (Value::U64(u), Scalar::I32) => Value::I32(*u as i32),
            (Value::U64(u), Scalar::F32) => Value::F32(*u as f32),
            (Value::U64(u), Scalar::Bool) => Value::Bool(*u != 0),
            // Rust's `as` saturates and maps NaN to 0; the clamp to the largest f32 below
            // the bound is WGSL's rule (the same integers result).
            (Value::F32(f), Scalar::I32) => Value::I32(f.clamp(i32::MIN as f32, I32_MAX_F) as i32),
            (Value::F32(f), Scalar::U32) => Value::U32(f.clamp(0.0, U32_MAX_F) as u32),
            (Value::F32(f), Scalar::Bool) => Value::Bool(*f != 0.0),
            _ => return type_err(format!("cast of {x} to {}", to.rust_name())),
        })
    })
}
