//! WGSL builtin functions on scalars and vectors, by their WGSL name (the IR's
//! [`crate::ir::Builtin::wgsl`]), with arguments in WGSL order. Float functions are computed in
//! `f32` with Rust's `std` (close to correctly rounded); WGSL allows the GPU an error per
//! function, which the differential test's tolerances state.

use super::error::{EvalError, type_err};
use super::ops::{binary, map1, map2, map3};
use super::value::Value;
use crate::ir::BinOp;

fn f(v: &Value) -> Result<f32, EvalError> {
    match v {
        Value::F32(x) => Ok(*x),
        _ => type_err(format!("expected f32, found {v}")),
    }
}

fn float1(v: &Value, g: impl Fn(f32) -> f32) -> Result<Value, EvalError> {
    map1(v, &mut |x| Ok(Value::F32(g(f(x)?))))
}

fn float2(a: &Value, b: &Value, g: impl Fn(f32, f32) -> f32) -> Result<Value, EvalError> {
    map2(a, b, &mut |x, y| Ok(Value::F32(g(f(x)?, f(y)?))))
}

fn float3(
    a: &Value,
    b: &Value,
    c: &Value,
    g: impl Fn(f32, f32, f32) -> f32,
) -> Result<Value, EvalError> {
    map3(a, b, c, &mut |x, y, z| {
        Ok(Value::F32(g(f(x)?, f(y)?, f(z)?)))
    })
}

/// An integer function on the 32 bits of an `i32` or `u32` component, keeping its type.
fn int1(v: &Value, g: impl Fn(u32) -> u32) -> Result<Value, EvalError> {
    map1(v, &mut |x| {
        Ok(match x {
            Value::I32(i) => Value::I32(g(*i as u32) as i32),
            Value::U32(u) => Value::U32(g(*u)),
            _ => return type_err(format!("expected an integer, found {x}")),
        })
    })
}

/// WGSL `sign`: -1, 0 or 1 (Rust's `signum` gives 1 for +0.0).
fn sign(x: f32) -> f32 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        x
    }
}

fn min_max(a: &Value, b: &Value, max: bool) -> Result<Value, EvalError> {
    map2(a, b, &mut |x, y| {
        Ok(match (x, y) {
            (Value::I32(p), Value::I32(q)) => Value::I32(if max { *p.max(q) } else { *p.min(q) }),
            (Value::U32(p), Value::U32(q)) => Value::U32(if max { *p.max(q) } else { *p.min(q) }),
            (Value::U64(p), Value::U64(q)) => Value::U64(if max { *p.max(q) } else { *p.min(q) }),
            (Value::F32(p), Value::F32(q)) => Value::F32(if max { p.max(*q) } else { p.min(*q) }),
            _ => return type_err(format!("min/max of {x} and {y}")),
        })
    })
}

fn dot(a: &Value, b: &Value) -> Result<Value, EvalError> {
    let (Value::Vector(x), Value::Vector(y)) = (a, b) else {
        return type_err("dot of non-vectors");
    };
    let mut acc: Option<Value> = None;
    for (p, q) in x.iter().zip(y) {
        let m = binary(BinOp::Mul, p, q)?;
        acc = Some(match acc {
            None => m,
            Some(s) => binary(BinOp::Add, &s, &m)?,
        });
    }
    acc.ok_or_else(|| EvalError::Type("dot of empty vectors".into()))
}

fn length(a: &Value) -> Result<f32, EvalError> {
    match a {
        Value::Vector(_) => Ok(f(&dot(a, a)?)?.sqrt()),
        s => Ok(f(s)?.abs()),
    }
}

fn smoothstep(lo: f32, hi: f32, x: f32) -> f32 {
    let t = ((x - lo) / (hi - lo)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Evaluates the WGSL builtin `name` on evaluated arguments (WGSL argument order).
pub fn call(name: &str, args: &[Value]) -> Result<Value, EvalError> {
    let a = |i: usize| {
        args.get(i)
            .ok_or_else(|| EvalError::Type(format!("`{name}` is missing argument {i}")))
    };
    Ok(match name {
        "abs" => map1(a(0)?, &mut |x| {
            Ok(match x {
                Value::I32(i) => Value::I32(i.wrapping_abs()),
                Value::U32(u) => Value::U32(*u),
                Value::F32(v) => Value::F32(v.abs()),
                _ => return type_err(format!("abs of {x}")),
            })
        })?,
        "sqrt" => float1(a(0)?, f32::sqrt)?,
        "inverseSqrt" => float1(a(0)?, |x| 1.0 / x.sqrt())?,
        "floor" => float1(a(0)?, f32::floor)?,
        "ceil" => float1(a(0)?, f32::ceil)?,
        // WGSL rounds halfway cases to even.
        "round" => float1(a(0)?, f32::round_ties_even)?,
        "fract" => float1(a(0)?, |x| x - x.floor())?,
        "trunc" => float1(a(0)?, f32::trunc)?,
        "sin" => float1(a(0)?, f32::sin)?,
        "cos" => float1(a(0)?, f32::cos)?,
        "tan" => float1(a(0)?, f32::tan)?,
        "asin" => float1(a(0)?, f32::asin)?,
        "acos" => float1(a(0)?, f32::acos)?,
        "atan" => float1(a(0)?, f32::atan)?,
        "sinh" => float1(a(0)?, f32::sinh)?,
        "cosh" => float1(a(0)?, f32::cosh)?,
        "tanh" => float1(a(0)?, f32::tanh)?,
        "exp" => float1(a(0)?, f32::exp)?,
        "exp2" => float1(a(0)?, f32::exp2)?,
        "log" => float1(a(0)?, f32::ln)?,
        "log2" => float1(a(0)?, f32::log2)?,
        "sign" => float1(a(0)?, sign)?,
        "radians" => float1(a(0)?, f32::to_radians)?,
        "degrees" => float1(a(0)?, f32::to_degrees)?,
        "saturate" => float1(a(0)?, |x| x.clamp(0.0, 1.0))?,
        "min" => min_max(a(0)?, a(1)?, false)?,
        "max" => min_max(a(0)?, a(1)?, true)?,
        // clamp(e, lo, hi) = min(max(e, lo), hi), also when lo > hi.
        "clamp" => min_max(&min_max(a(0)?, a(1)?, true)?, a(2)?, false)?,
        "pow" => float2(a(0)?, a(1)?, f32::powf)?,
        "atan2" => float2(a(0)?, a(1)?, f32::atan2)?,
        "step" => float2(a(0)?, a(1)?, |edge, x| if edge <= x { 1.0 } else { 0.0 })?,
        "fma" => float3(a(0)?, a(1)?, a(2)?, |x, y, z| x * y + z)?,
        "smoothstep" => float3(a(0)?, a(1)?, a(2)?, smoothstep)?,
        "mix" => float3(a(0)?, a(1)?, a(2)?, |x, y, t| x * (1.0 - t) + y * t)?,
        "dot" => dot(a(0)?, a(1)?)?,
        "length" => Value::F32(length(a(0)?)?),
        "distance" => Value::F32(length(&binary(BinOp::Sub, a(0)?, a(1)?)?)?),
        "normalize" => {
            let l = length(a(0)?)?;
            float1(a(0)?, |x| x / l)?
        }
        "cross" => {
            let (Value::Vector(x), Value::Vector(y)) = (a(0)?, a(1)?) else {
                return type_err("cross of non-vectors");
            };
            let c = |i: usize| f(&x[i]);
            let d = |i: usize| f(&y[i]);
            Value::Vector(vec![
                Value::F32(c(1)? * d(2)? - c(2)? * d(1)?),
                Value::F32(c(2)? * d(0)? - c(0)? * d(2)?),
                Value::F32(c(0)? * d(1)? - c(1)? * d(0)?),
            ])
        }
        "reflect" => {
            // e1 - 2 * dot(e2, e1) * e2
            let k = 2.0 * f(&dot(a(1)?, a(0)?)?)?;
            map2(a(0)?, a(1)?, &mut |e, n| Ok(Value::F32(f(e)? - k * f(n)?)))?
        }
        "select" => match a(2)? {
            Value::Bool(c) => if *c { a(1)? } else { a(0)? }.clone(),
            Value::Vector(_) => map3(a(0)?, a(1)?, a(2)?, &mut |x, y, c| {
                Ok(if *c == Value::Bool(true) {
                    y.clone()
                } else {
                    x.clone()
                })
            })?,
            c => return type_err(format!("select condition {c}")),
        },
        "countOneBits" => int1(a(0)?, u32::count_ones)?,
        "countLeadingZeros" => int1(a(0)?, u32::leading_zeros)?,
        "countTrailingZeros" => int1(a(0)?, u32::trailing_zeros)?,
        "reverseBits" => int1(a(0)?, u32::reverse_bits)?,
        "bitcast<u32>" => map1(a(0)?, &mut |x| Ok(Value::U32(bits(x)?)))?,
        "bitcast<i32>" => map1(a(0)?, &mut |x| Ok(Value::I32(bits(x)? as i32)))?,
        "bitcast<f32>" => map1(a(0)?, &mut |x| Ok(Value::F32(f32::from_bits(bits(x)?))))?,
        other => return Err(EvalError::Unsupported(format!("the builtin `{other}`"))),
    })
}

fn bits(x: &Value) -> Result<u32, EvalError> {
    match x {
        Value::Bool(_) => type_err("bitcast of bool"),
        v => v
            .bits()
            .ok_or_else(|| EvalError::Type(format!("bitcast of {v}"))),
    }
}
