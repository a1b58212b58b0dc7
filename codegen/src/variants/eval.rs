//! Constant evaluation of IR expressions under an axis environment.

use super::env::Env;
use crate::ir::{BinOp, Expr, ExprKind, Lit, Module, Scalar, Ty, UnOp};

/// A constant value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// Boolean.
    Bool(bool),
    /// Integer (wrapped to the expression's type: `i32`, `u32` or `u64`).
    Int(i128),
    /// Float.
    Float(f64),
}

impl Value {
    /// The literal of this value at the given type.
    pub fn to_lit(self, ty: &Ty) -> Lit {
        let s = ty.scalar().unwrap_or(Scalar::AbstractInt);
        match self {
            Value::Bool(b) => Lit::Bool(b),
            Value::Int(i) => Lit::Int(i, s),
            Value::Float(f) => Lit::Float(f, s),
        }
    }
}

fn wrap(v: i128, ty: &Ty) -> Option<i128> {
    match ty.scalar() {
        Some(Scalar::U32) => Some(v as u32 as i128),
        Some(Scalar::I32) => Some(v as i32 as i128),
        Some(Scalar::U64) => Some(v as u64 as i128),
        Some(Scalar::AbstractInt) => Some(v),
        _ => None,
    }
}

/// Bits of an integer type (shift amounts must be below it).
fn int_bits(ty: &Ty) -> u32 {
    if ty.scalar() == Some(Scalar::U64) {
        64
    } else {
        32
    }
}

/// The largest `f32` not above `u64::MAX` (2^64 - 2^40): WGSL's saturation bound.
const U64_MAX_F: f64 = 18_446_742_974_197_923_840.0;

/// Evaluates a constant expression (literals, axes, consts, operators, casts); `None` when it
/// is not constant. `&&`/`||` short-circuit, so `false && x` is constant even when `x` is not.
pub fn eval(e: &Expr, m: &Module, env: &Env) -> Option<Value> {
    Some(match &e.kind {
        ExprKind::Lit(Lit::Bool(b)) => Value::Bool(*b),
        ExprKind::Lit(Lit::Int(i, _)) => Value::Int(*i),
        ExprKind::Lit(Lit::Float(f, _)) => Value::Float(*f),
        ExprKind::Axis(a) => match env.values.get(*a)? {
            Lit::Bool(b) => Value::Bool(*b),
            Lit::Int(i, _) => Value::Int(*i),
            Lit::Float(f, _) => Value::Float(*f),
        },
        ExprKind::Const(c) => eval(&m.consts[*c].value, m, env)?,
        ExprKind::Unary(op, x) => match (op, eval(x, m, env)?) {
            (UnOp::Not, Value::Bool(b)) => Value::Bool(!b),
            (UnOp::Neg, Value::Int(i)) => Value::Int(wrap(-i, &e.ty)?),
            (UnOp::Neg, Value::Float(f)) => Value::Float(-f),
            (UnOp::BitNot, Value::Int(i)) => Value::Int(wrap(!i, &e.ty)?),
            _ => return None,
        },
        ExprKind::Cast(x) => match (eval(x, m, env)?, e.ty.scalar()?) {
            (Value::Bool(b), s) if s.is_int() => Value::Int(b.into()),
            // Rounded once, to `f32` (through `f64` a `u64` would round twice).
            (Value::Int(i), Scalar::F32) if x.ty == Ty::U64 => Value::Float(i as f32 as f64),
            (Value::Int(i), Scalar::F32) => Value::Float(i as f64),
            (Value::Int(i), _) => Value::Int(wrap(i, &e.ty)?),
            (Value::Float(f), Scalar::F32) => Value::Float(f),
            (Value::Float(f), Scalar::U32) => Value::Int(f.clamp(0.0, u32::MAX as f64) as i128),
            (Value::Float(f), Scalar::U64) => Value::Int(f.clamp(0.0, U64_MAX_F) as i128),
            (Value::Float(f), Scalar::I32) => {
                Value::Int(f.clamp(i32::MIN as f64, i32::MAX as f64) as i128)
            }
            _ => return None,
        },
        ExprKind::Binary(op, a, b) => {
            let av = eval(a, m, env);
            match (op, av) {
                (BinOp::And, Some(Value::Bool(false))) => return Some(Value::Bool(false)),
                (BinOp::Or, Some(Value::Bool(true))) => return Some(Value::Bool(true)),
                _ => {}
            }
            let bv = eval(b, m, env);
            match (op, bv) {
                (BinOp::And, Some(Value::Bool(false))) => return Some(Value::Bool(false)),
                (BinOp::Or, Some(Value::Bool(true))) => return Some(Value::Bool(true)),
                _ => {}
            }
            binary(*op, av?, bv?, &e.ty)?
        }
        _ => return None,
    })
}

fn binary(op: BinOp, a: Value, b: Value, ty: &Ty) -> Option<Value> {
    use BinOp::*;
    Some(match (a, b) {
        (Value::Bool(x), Value::Bool(y)) => Value::Bool(match op {
            And | BitAnd => x && y,
            Or | BitOr => x || y,
            BitXor | Ne => x != y,
            Eq => x == y,
            _ => return None,
        }),
        (Value::Int(x), Value::Int(y)) => {
            let bits = int_bits(ty);
            let amount = || u32::try_from(y).ok().filter(|s| *s < bits);
            match op {
                Eq => Value::Bool(x == y),
                Ne => Value::Bool(x != y),
                Lt => Value::Bool(x < y),
                Le => Value::Bool(x <= y),
                Gt => Value::Bool(x > y),
                Ge => Value::Bool(x >= y),
                _ => Value::Int(wrap(
                    match op {
                        Add => x.wrapping_add(y),
                        Sub => x.wrapping_sub(y),
                        Mul => x.wrapping_mul(y),
                        Div => x.checked_div(y)?,
                        Rem => x.checked_rem(y)?,
                        BitAnd => x & y,
                        BitOr => x | y,
                        BitXor => x ^ y,
                        Shl => x.checked_shl(amount()?)?,
                        // Unsigned values are non-negative here, so `>>` is logical on them
                        // and arithmetic on `i32`.
                        Shr => x >> amount()?,
                        _ => return None,
                    },
                    ty,
                )?),
            }
        }
        (Value::Float(x), Value::Float(y)) => match op {
            Add => Value::Float(x + y),
            Sub => Value::Float(x - y),
            Mul => Value::Float(x * y),
            Div => Value::Float(x / y),
            Eq => Value::Bool(x == y),
            Ne => Value::Bool(x != y),
            Lt => Value::Bool(x < y),
            Le => Value::Bool(x <= y),
            Gt => Value::Bool(x > y),
            Ge => Value::Bool(x >= y),
            _ => return None,
        },
        (Value::Int(x), Value::Float(_)) => binary(op, Value::Float(x as f64), b, ty)?,
        (Value::Float(_), Value::Int(y)) => binary(op, a, Value::Float(y as f64), ty)?,
        _ => return None,
    })
}
