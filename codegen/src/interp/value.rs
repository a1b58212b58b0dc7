//! Runtime values of the host evaluator: scalars, vectors, and the composite shapes (arrays,
//! structs) a kernel interpreter will need.

use crate::ir::{Scalar, Ty};
use std::fmt;

/// A value the evaluator computes. Vectors hold scalar components only.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// `bool`
    Bool(bool),
    /// `i32`
    I32(i32),
    /// `u32`
    U32(u32),
    /// `u64` (in buffers: two 32-bit words, the low one first)
    U64(u64),
    /// `f32`
    F32(f32),
    /// `vecN<T>`: 2 to 4 scalar components of one type.
    Vector(Vec<Value>),
    /// `array<T, N>`
    Array(Vec<Value>),
    /// A struct: its fields in declaration order.
    Struct(Vec<Value>),
}

impl Value {
    /// The scalar type of a scalar or vector value.
    pub fn scalar(&self) -> Option<Scalar> {
        match self {
            Value::Bool(_) => Some(Scalar::Bool),
            Value::I32(_) => Some(Scalar::I32),
            Value::U32(_) => Some(Scalar::U32),
            Value::U64(_) => Some(Scalar::U64),
            Value::F32(_) => Some(Scalar::F32),
            Value::Vector(c) => c.first().and_then(Value::scalar),
            _ => None,
        }
    }

    /// The components of a vector, or the scalar itself as one component.
    pub fn components(&self) -> Vec<Value> {
        match self {
            Value::Vector(c) => c.clone(),
            v => vec![v.clone()],
        }
    }

    /// The zero value of a type (`Vec3::ZERO`, `0u32`, ..), where the type has one here.
    pub fn zero(ty: &Ty) -> Option<Value> {
        Some(match ty {
            Ty::Scalar(s) => scalar_from_f64(*s, 0.0),
            Ty::Vector(n, s) => Value::Vector(vec![scalar_from_f64(*s, 0.0); *n as usize]),
            _ => return None,
        })
    }

    /// The buffer words of a scalar, low first: two for a `u64`, one for the others.
    pub fn words(&self) -> Option<Vec<u32>> {
        match self {
            Value::U64(u) => Some(vec![*u as u32, (*u >> 32) as u32]),
            v => v.bits().map(|b| vec![b]),
        }
    }

    /// A scalar of type `s` from its buffer words, low first (see [`Value::words`]).
    pub fn from_words(s: Scalar, words: &[u32]) -> Value {
        match (s, words) {
            (Scalar::U64, [lo, hi, ..]) => Value::U64(u64::from(*lo) | (u64::from(*hi) << 32)),
            (s, w) => Value::from_bits(s, w.first().copied().unwrap_or(0)),
        }
    }

    /// The 32 bits of a 32-bit scalar as stored in a buffer (`bool` as 0 or 1); `None` for a
    /// `u64` (see [`Value::words`]) and composites.
    pub fn bits(&self) -> Option<u32> {
        Some(match self {
            Value::Bool(b) => *b as u32,
            Value::I32(i) => *i as u32,
            Value::U32(u) => *u,
            Value::F32(f) => f.to_bits(),
            _ => return None,
        })
    }

    /// A scalar of type `s` from its 32 buffer bits (`bool`: non-zero is `true`).
    pub fn from_bits(s: Scalar, bits: u32) -> Value {
        match s.concretize() {
            Scalar::Bool => Value::Bool(bits != 0),
            Scalar::I32 => Value::I32(bits as i32),
            Scalar::U32 => Value::U32(bits),
            Scalar::U64 => Value::U64(bits.into()),
            _ => Value::F32(f32::from_bits(bits)),
        }
    }
}

/// A scalar of type `s` (abstract types concretized) holding `x`, converted as Rust's `as`
/// does (used for literals, which the front end has already range-checked).
pub(crate) fn scalar_from_f64(s: Scalar, x: f64) -> Value {
    match s.concretize() {
        Scalar::Bool => Value::Bool(x != 0.0),
        Scalar::I32 => Value::I32(x as i64 as i32),
        Scalar::U32 => Value::U32(x as i64 as u32),
        Scalar::U64 => Value::U64(x as u64),
        _ => Value::F32(x as f32),
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Bool(b) => write!(f, "{b}"),
            Value::I32(i) => write!(f, "{i}i32"),
            Value::U32(u) => write!(f, "{u}u32"),
            Value::U64(u) => write!(f, "{u}u64"),
            Value::F32(x) => write!(f, "{x:?}f32 (0x{:08x})", x.to_bits()),
            Value::Vector(c) | Value::Array(c) | Value::Struct(c) => {
                let open = if matches!(self, Value::Struct(_)) {
                    "{"
                } else {
                    "["
                };
                let close = if open == "{" { "}" } else { "]" };
                write!(f, "{open}")?;
                for (i, v) in c.iter().enumerate() {
                    if i > 0 {
                        write!(f, ", ")?;
                    }
                    write!(f, "{v}")?;
                }
                write!(f, "{close}")
            }
        }
    }
}
