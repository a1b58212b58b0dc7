//! A host evaluator of the typed IR with the DSL's documented runtime semantics (WGSL's), the
//! reference the generated differential tests compare the GPU against.
//!
//! [`eval_expr`] evaluates one [`Expr`] of a module given the values of the function's locals:
//! literals, locals, consts, axes, unary and binary operators (with `&&`/`||` short-circuit),
//! casts, swizzles, field access, indexing, constructors and the scalar/vector builtins of the
//! language guide. What it cannot evaluate (resources, textures, atomics, derivatives, subgroup
//! operations, calls of module functions, matrices) is an [`EvalError::Unsupported`] naming it.
//!
//! The semantics are written from the WGSL specification's rules, independently of the
//! printer: see [`ops`] for integer overflow, shifts, division by zero and float-to-int
//! conversion, and [`builtins`] for the functions. Whole-kernel execution (statements,
//! workgroups, barriers, subgroups) is meant to be built on top of this expression core, with
//! [`Value`] growing by the arrays and structs it already has variants for.
//!
//! Abstract literals (unsuffixed `1`, `0.5`) take the concrete type their context gives them,
//! as WGSL's automatic conversions do: [`eval_expr`] passes the expected scalar down into
//! abstract-typed subexpressions.

pub mod builtins;
mod error;
pub mod ops;
mod value;

#[cfg(test)]
mod tests;

pub use error::EvalError;
pub use value::Value;

use crate::ir::{BinOp, Expr, ExprKind, Lit, Module, Scalar, Ty};
use crate::variants::Env;
use value::scalar_from_f64;

/// Evaluates `expr`, an expression of a function of `module`, in the variant `env`, with
/// `locals[i]` the value of the function's local `i` (`Function::locals` order: parameters
/// first). Locals the expression does not read may hold anything.
pub fn eval_expr(
    module: &Module,
    env: &Env,
    expr: &Expr,
    locals: &[Value],
) -> Result<Value, EvalError> {
    Evaluator {
        module,
        env,
        locals,
    }
    .eval(expr, None)
}

struct Evaluator<'a> {
    module: &'a Module,
    env: &'a Env,
    locals: &'a [Value],
}

/// The concrete scalar an expression of type `ty` evaluates to, given the scalar its context
/// expects for abstract types.
fn target(ty: &Ty, want: Option<Scalar>) -> Option<Scalar> {
    let s = ty.scalar()?;
    Some(match s {
        Scalar::AbstractInt | Scalar::AbstractFloat => want
            .filter(|w| *w != Scalar::Bool)
            .unwrap_or(s.concretize()),
        s => s,
    })
}

fn lit(l: Lit, s: Option<Scalar>) -> Value {
    match (l, s.map(Scalar::concretize)) {
        (Lit::Bool(b), _) => Value::Bool(b),
        (Lit::Int(i, _), Some(Scalar::U32)) => Value::U32(i as u32),
        (Lit::Int(i, _), Some(Scalar::F32)) => Value::F32(i as f32),
        (Lit::Int(i, _), _) => Value::I32(i as i32),
        (Lit::Float(x, _), _) => scalar_from_f64(Scalar::F32, x),
    }
}

impl Evaluator<'_> {
    fn eval(&self, e: &Expr, want: Option<Scalar>) -> Result<Value, EvalError> {
        let s = target(&e.ty, want);
        match &e.kind {
            ExprKind::Lit(l) => Ok(lit(*l, s)),
            ExprKind::Local(l) => self
                .locals
                .get(*l)
                .cloned()
                .ok_or(EvalError::UnknownLocal(*l)),
            ExprKind::Const(c) => {
                let c = &self.module.consts[*c];
                let v = Evaluator {
                    locals: &[],
                    ..*self
                }
                .eval(&c.value, c.ty.scalar())?;
                Ok(v)
            }
            ExprKind::Axis(a) => match self.env.values.get(*a) {
                Some(l) => Ok(lit(*l, s)),
                None => Err(EvalError::Type(format!("axis {a} has no value"))),
            },
            ExprKind::Unary(op, x) => ops::unary(*op, &self.eval(x, s)?),
            ExprKind::Binary(op, a, b) => self.binary(*op, a, b, s),
            ExprKind::Cast(x) => {
                let to = s.ok_or_else(|| EvalError::Unsupported(format!("cast to {:?}", e.ty)))?;
                ops::cast(&self.eval(x, None)?, to)
            }
            ExprKind::Field(b, i) => match self.eval(b, None)? {
                Value::Struct(fields) => fields
                    .get(*i)
                    .cloned()
                    .ok_or_else(|| EvalError::Type(format!("no field {i}"))),
                v => Err(EvalError::Type(format!("field {i} of {v}"))),
            },
            ExprKind::Swizzle(b, sw) => {
                let v = self.eval(b, s)?;
                let Value::Vector(c) = &v else {
                    return Err(EvalError::Type(format!("swizzle of {v}")));
                };
                let picked = sw
                    .chars()
                    .map(|ch| {
                        let i = "xyzw".find(ch).unwrap_or(4);
                        c.get(i).cloned().ok_or(EvalError::OutOfBounds {
                            index: i as i64,
                            len: c.len(),
                        })
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                Ok(if picked.len() == 1 {
                    picked.into_iter().next().expect("one component")
                } else {
                    Value::Vector(picked)
                })
            }
            ExprKind::Index(b, i) => {
                let base = self.eval(b, s)?;
                let index = match self.eval(i, None)? {
                    Value::I32(k) => k as i64,
                    Value::U32(k) => k as i64,
                    v => return Err(EvalError::Type(format!("index {v}"))),
                };
                let (Value::Vector(items) | Value::Array(items)) = &base else {
                    return Err(EvalError::Unsupported(format!("indexing {base}")));
                };
                usize::try_from(index)
                    .ok()
                    .and_then(|k| items.get(k).cloned())
                    .ok_or(EvalError::OutOfBounds {
                        index,
                        len: items.len(),
                    })
            }
            ExprKind::Construct(args) => self.construct(&e.ty, args, s),
            ExprKind::Builtin(b, args) => {
                if b.pointer_first || b.subgroup {
                    return Err(EvalError::Unsupported(format!("the builtin `{}`", b.wgsl)));
                }
                let arg_want = if b.wgsl.starts_with("bitcast") {
                    None
                } else {
                    s
                };
                let vals = args
                    .iter()
                    .map(|a| self.eval(a, arg_want))
                    .collect::<Result<Vec<_>, _>>()?;
                builtins::call(b.wgsl, &vals)
            }
            ExprKind::Global(g) => Err(EvalError::Unsupported(format!(
                "reading the static `{}`",
                self.module.globals[*g].name
            ))),
            ExprKind::Call(f, _) => Err(EvalError::Unsupported(format!(
                "calling the function `{}`",
                self.module.functions[*f].name
            ))),
            ExprKind::AddrOf(_) | ExprKind::Deref(_) => {
                Err(EvalError::Unsupported("pointers".into()))
            }
        }
    }

    fn binary(&self, op: BinOp, a: &Expr, b: &Expr, s: Option<Scalar>) -> Result<Value, EvalError> {
        match op {
            BinOp::And | BinOp::Or => {
                let l = self.eval(a, None)?;
                if l == Value::Bool(op == BinOp::Or) {
                    return Ok(l);
                }
                let r = self.eval(b, None)?;
                ops::binary(op, &l, &r)
            }
            BinOp::Shl | BinOp::Shr => {
                let l = self.eval(a, s)?;
                let r = self.eval(b, Some(Scalar::U32))?;
                ops::binary(op, &l, &r)
            }
            _ if op.is_comparison() => {
                // Operands meet at their common type: a concrete side decides an abstract one.
                let common = match (a.ty.scalar(), b.ty.scalar()) {
                    (Some(x), Some(y)) => x.unify(y).map(Scalar::concretize),
                    _ => None,
                };
                let l = self.eval(a, common)?;
                let r = self.eval(b, common)?;
                ops::binary(op, &l, &r)
            }
            _ => {
                let l = self.eval(a, s)?;
                let r = self.eval(b, s)?;
                ops::binary(op, &l, &r)
            }
        }
    }

    fn construct(&self, ty: &Ty, args: &[Expr], s: Option<Scalar>) -> Result<Value, EvalError> {
        match ty {
            Ty::Vector(n, _) => {
                let s = s.ok_or_else(|| EvalError::Type("vector without scalar".into()))?;
                let n = *n as usize;
                if args.is_empty() {
                    return Value::zero(&Ty::Vector(n as u8, s))
                        .ok_or_else(|| EvalError::Type("zero vector".into()));
                }
                let vals = args
                    .iter()
                    .map(|a| self.eval(a, Some(s)))
                    .collect::<Result<Vec<_>, _>>()?;
                let comps: Vec<Value> = match vals.as_slice() {
                    // `Vec3::splat(x)`, `Vec3::ONE`.
                    [one] if !matches!(one, Value::Vector(_)) => vec![one.clone(); n],
                    // `v.as_uvec3()`: a conversion, or `vec3<f32>(v)`.
                    vals => vals.iter().flat_map(Value::components).collect(),
                };
                if comps.len() != n {
                    return Err(EvalError::Type(format!(
                        "{} components for a {n}-vector",
                        comps.len()
                    )));
                }
                let comps = comps
                    .iter()
                    .map(|c| ops::cast(c, s))
                    .collect::<Result<Vec<_>, _>>()?;
                Ok(Value::Vector(comps))
            }
            Ty::Array(elem, _) => Ok(Value::Array(
                args.iter()
                    .map(|a| self.eval(a, elem.scalar()))
                    .collect::<Result<_, _>>()?,
            )),
            Ty::Struct(id) => {
                let fields = &self.module.structs[*id].fields;
                Ok(Value::Struct(
                    args.iter()
                        .zip(fields)
                        .map(|(a, fl)| self.eval(a, fl.ty.scalar()))
                        .collect::<Result<_, _>>()?,
                ))
            }
            Ty::Scalar(_) => match args {
                [a] => ops::cast(&self.eval(a, s)?, s.unwrap_or(Scalar::F32)),
                _ => Err(EvalError::Type("scalar constructor".into())),
            },
            t => Err(EvalError::Unsupported(format!("constructing {t:?}"))),
        }
    }
}
