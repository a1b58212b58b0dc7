//! Expression evaluation: literals, locals, statics, consts, axes, operators (with `&&`/`||`
//! short-circuit), casts, swizzles, fields, indexing, constructors, builtins and calls of
//! module functions.

use super::sync::SyncOp;
use super::value::scalar_from_f64;
use super::{EvalError, Machine, Value, builtins, matrix, ops};
use crate::ir::{BinOp, Expr, ExprKind, Lit, Scalar, Ty, UnOp};

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
        (Lit::Int(i, _), Some(Scalar::U64)) => Value::U64(i as u64),
        (Lit::Int(i, _), Some(Scalar::F32)) => Value::F32(i as f32),
        (Lit::Int(i, _), _) => Value::I32(i as i32),
        (Lit::Float(x, _), _) => scalar_from_f64(Scalar::F32, x),
    }
}

impl Machine<'_> {
    /// Evaluates `e` with the function's locals `locals`; abstract literals take `want`.
    pub(crate) fn eval(
        &mut self,
        locals: &[Value],
        e: &Expr,
        want: Option<Scalar>,
    ) -> Result<Value, EvalError> {
        let s = target(&e.ty, want);
        match &e.kind {
            ExprKind::Lit(l) => Ok(lit(*l, s)),
            ExprKind::Local(l) => locals.get(*l).cloned().ok_or(EvalError::UnknownLocal(*l)),
            ExprKind::Const(c) => {
                let c = &self.module.consts[*c];
                self.eval(&[], &c.value, c.ty.scalar())
            }
            ExprKind::Axis(a) => match self.env.values.get(*a) {
                Some(l) => Ok(lit(*l, s)),
                None => Err(EvalError::Type(format!("axis {a} has no value"))),
            },
            ExprKind::Unary(UnOp::Neg, x) if matches!(x.ty, Ty::Matrix(..)) => {
                matrix::negate(&self.eval(locals, x, s)?)
            }
            ExprKind::Unary(op, x) => ops::unary(*op, &self.eval(locals, x, s)?),
            // A static's element or field, read without copying the whole static.
            ExprKind::Index(..) | ExprKind::Field(..) if Self::rooted_at_global(e) => {
                self.read_global_place(locals, e)
            }
            ExprKind::Binary(op, a, b) => self.binary(locals, *op, a, b, s),
            ExprKind::Cast(x) => {
                let to = s.ok_or_else(|| EvalError::Unsupported(format!("cast to {:?}", e.ty)))?;
                ops::cast(&self.eval(locals, x, None)?, to)
            }
            ExprKind::Field(b, i) => match self.eval(locals, b, None)? {
                Value::Struct(fields) => fields
                    .get(*i)
                    .cloned()
                    .ok_or_else(|| EvalError::Type(format!("no field {i}"))),
                v => Err(EvalError::Type(format!("field {i} of {v}"))),
            },
            ExprKind::Swizzle(b, sw) => {
                let v = self.eval(locals, b, s)?;
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
                Ok(match <[Value; 1]>::try_from(picked) {
                    Ok([one]) => one,
                    Err(picked) => Value::Vector(picked),
                })
            }
            ExprKind::Index(b, i) => {
                let base = self.eval(locals, b, s)?;
                let index = match self.eval(locals, i, None)? {
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
            ExprKind::Construct(args) => self.construct(locals, &e.ty, args, s),
            ExprKind::Builtin(b, args) => {
                // `arr.len()`: the argument is the static (the printer writes the `&`).
                if let ("arrayLength", [array]) = (b.wgsl, args.as_slice()) {
                    return match self.eval(locals, array, None)? {
                        Value::Array(items) => Ok(Value::U32(items.len() as u32)),
                        v => Err(EvalError::Type(format!("the length of {v}"))),
                    };
                }
                if b.subgroup {
                    let vals = args
                        .iter()
                        .map(|a| self.eval(locals, a, s))
                        .collect::<Result<Vec<_>, _>>()?;
                    let op = SyncOp::Subgroup {
                        wgsl: b.wgsl,
                        args: vals,
                    };
                    return self.sync(op, e.span)?.ok_or_else(|| {
                        EvalError::Type(format!("`{}` resumed without a result", b.wgsl))
                    });
                }
                if matches!(b.wgsl, "workgroupBarrier" | "storageBarrier") {
                    self.sync(SyncOp::Barrier(b.wgsl), e.span)?;
                    return Ok(Value::Struct(vec![]));
                }
                if b.wgsl == "workgroupUniformLoad" {
                    // A workgroup barrier, then every invocation loads the same value.
                    self.sync(SyncOp::Barrier(b.wgsl), e.span)?;
                    let [place] = args.as_slice() else {
                        return Err(EvalError::Type(
                            "`workgroupUniformLoad` without its place".into(),
                        ));
                    };
                    return match place.ty {
                        Ty::Atomic(_) => self.atomic(locals, "atomicLoad", args),
                        _ => self.eval(locals, place, s),
                    };
                }
                if b.pointer_first && b.wgsl.starts_with("atomic") {
                    return self.atomic(locals, b.wgsl, args);
                }
                if b.pointer_first {
                    return Err(EvalError::Unsupported(format!("the builtin `{}`", b.wgsl)));
                }
                if let Some(v) = self.texture_builtin(locals, b.wgsl, args) {
                    return v;
                }
                if b.wgsl == "transpose"
                    && let [m] = args.as_slice()
                {
                    return matrix::transpose(&self.eval(locals, m, None)?);
                }
                let arg_want = if b.wgsl.starts_with("bitcast") {
                    None
                } else {
                    s
                };
                let vals = args
                    .iter()
                    .map(|a| self.eval(locals, a, arg_want))
                    .collect::<Result<Vec<_>, _>>()?;
                builtins::call(b.wgsl, &vals)
            }
            ExprKind::Global(g) => {
                self.track(*g, &[], e.span, false)?;
                self.global(*g).cloned()
            }
            ExprKind::Call(f, args) => {
                let callee = &self.module.functions[*f];
                let vals = args
                    .iter()
                    .zip(&callee.params)
                    .map(|(a, p)| self.eval(locals, a, callee.locals[p.local].ty.scalar()))
                    .collect::<Result<Vec<_>, _>>()?;
                Ok(self.call(*f, vals)?.unwrap_or(Value::Struct(vec![])))
            }
            ExprKind::AddrOf(_) | ExprKind::Deref(_) => {
                Err(EvalError::Unsupported("pointers".into()))
            }
        }
    }

    fn binary(
        &mut self,
        locals: &[Value],
        op: BinOp,
        a: &Expr,
        b: &Expr,
        s: Option<Scalar>,
    ) -> Result<Value, EvalError> {
        match op {
            BinOp::And | BinOp::Or => {
                let l = self.eval(locals, a, None)?;
                if l == Value::Bool(op == BinOp::Or) {
                    return Ok(l);
                }
                let r = self.eval(locals, b, None)?;
                ops::binary(op, &l, &r)
            }
            BinOp::Shl | BinOp::Shr => {
                let l = self.eval(locals, a, s)?;
                let r = self.eval(locals, b, Some(Scalar::U32))?;
                ops::binary(op, &l, &r)
            }
            _ if op.is_comparison() => {
                // Operands meet at their common type: a concrete side decides an abstract one.
                let common = match (a.ty.scalar(), b.ty.scalar()) {
                    (Some(x), Some(y)) => x.unify(y).map(Scalar::concretize),
                    _ => None,
                };
                let l = self.eval(locals, a, common)?;
                let r = self.eval(locals, b, common)?;
                ops::binary(op, &l, &r)
            }
            _ if matches!(a.ty, Ty::Matrix(..)) || matches!(b.ty, Ty::Matrix(..)) => {
                let l = self.eval(locals, a, Some(Scalar::F32))?;
                let r = self.eval(locals, b, Some(Scalar::F32))?;
                matrix::binary(op, &l, &r, &a.ty, &b.ty)
            }
            _ => {
                let l = self.eval(locals, a, s)?;
                let r = self.eval(locals, b, s)?;
                ops::binary(op, &l, &r)
            }
        }
    }

    /// An atomic builtin on the static place `args[0]` (atomics live only in storage and
    /// workgroup memory). Invocations of a dispatch run one at a time, so each is indivisible.
    fn atomic(&mut self, locals: &[Value], wgsl: &str, args: &[Expr]) -> Result<Value, EvalError> {
        let [place, rest @ ..] = args else {
            return Err(EvalError::Type(format!("`{wgsl}` without its atomic")));
        };
        let operand = match rest {
            // An unsuffixed literal operand takes the atomic's scalar (`A.fetch_add(1)`).
            [v] => {
                let want = match place.ty {
                    Ty::Atomic(s) => Some(s),
                    ref t => t.scalar(),
                };
                Some(self.eval(locals, v, want)?)
            }
            [] => None,
            _ => {
                return Err(EvalError::Unsupported(format!(
                    "`{wgsl}` with {} operands",
                    rest.len()
                )));
            }
        };
        let slot = self.global_place_mut(locals, place)?;
        let old = slot.clone();
        let Some(v) = operand else {
            return Ok(old);
        };
        // `Atomic<u64>`'s `fetch_min`/`fetch_max` return nothing (`()`).
        let unit = matches!(old, Value::U64(_));
        let new = match wgsl {
            "atomicStore" | "atomicExchange" => v,
            "atomicAdd" => ops::binary(BinOp::Add, &old, &v)?,
            "atomicSub" => ops::binary(BinOp::Sub, &old, &v)?,
            "atomicAnd" => ops::binary(BinOp::BitAnd, &old, &v)?,
            "atomicOr" => ops::binary(BinOp::BitOr, &old, &v)?,
            "atomicXor" => ops::binary(BinOp::BitXor, &old, &v)?,
            "atomicMin" => builtins::call("min", &[old.clone(), v])?,
            "atomicMax" => builtins::call("max", &[old.clone(), v])?,
            other => return Err(EvalError::Unsupported(format!("the builtin `{other}`"))),
        };
        *slot = new;
        Ok(if wgsl == "atomicStore" || unit {
            Value::Struct(vec![])
        } else {
            old
        })
    }

    fn construct(
        &mut self,
        locals: &[Value],
        ty: &Ty,
        args: &[Expr],
        s: Option<Scalar>,
    ) -> Result<Value, EvalError> {
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
                    .map(|a| self.eval(locals, a, Some(s)))
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
                    .map(|a| self.eval(locals, a, elem.scalar()))
                    .collect::<Result<_, _>>()?,
            )),
            Ty::Struct(id) => {
                let fields = &self.module.structs[*id].fields;
                Ok(Value::Struct(
                    args.iter()
                        .zip(fields)
                        .map(|(a, fl)| self.eval(locals, a, fl.ty.scalar()))
                        .collect::<Result<_, _>>()?,
                ))
            }
            Ty::Matrix(c, r) => {
                let vals = args
                    .iter()
                    .map(|a| self.eval(locals, a, Some(Scalar::F32)))
                    .collect::<Result<Vec<_>, _>>()?;
                matrix::construct(*c, *r, vals)
            }
            Ty::Scalar(_) => match args {
                [a] => ops::cast(&self.eval(locals, a, s)?, s.unwrap_or(Scalar::F32)),
                _ => Err(EvalError::Type("scalar constructor".into())),
            },
            t => Err(EvalError::Unsupported(format!("constructing {t:?}"))),
        }
    }
}
