//! How far the driver may move a float result from the host's step-by-step evaluation.
//!
//! Vulkan lets a driver reassociate float arithmetic and fuse a multiply into an add unless the
//! SPIR-V says `NoContraction` (naga never does), and llvmpipe does both (`3.0 + (x + -2.0)`
//! becomes `x + 1.0`). Each operation is still correctly rounded, so a lone operation on exact
//! operands is exact; only chains can move. This module computes a running error bound per
//! node, on one input row:
//!
//! - `a ± b` where an operand is itself arithmetic: `err(a) + err(b) + ε·mass`, with `mass`
//!   the sum of the magnitudes of every term of the chain (covers any regrouping of the chain,
//!   across `floor` too, and a fused product); `a * b`: `|a|·err(b) + |b|·err(a) +
//!   err(a)·err(b)`, plus `2ε·|a·b|` when an operand is inexact or a product (the product's
//!   own rounding, factoring, regrouped constants). `dot` and `fma` (`mul_add`) may round their
//!   products or not and sum in any order: `ε·Σ|products|` plus the propagated error.
//! - Continuous functions (`abs`, `min`, `max`, `clamp`, `saturate`, negation, `select`,
//!   swizzles, constructors) keep their operands' largest error.
//! - Discontinuous ones (`floor`, `ceil`, `trunc`, `round`, `fract`, `step`, `sign`,
//!   comparisons, float-to-int casts) are exact when no value within the operand's error
//!   crosses a step, and **indeterminate** otherwise: the row is not compared, as for NaN.
//! - Approximate functions (`/`, `sqrt`, `sin`, ..) have their stated tolerance only on exact
//!   operands: an operand with a non-zero error makes the row indeterminate.

use codegen::interp::{Value, eval_expr};
use codegen::ir::{BinOp, Expr, ExprKind, Module, UnOp};
use codegen::variants::Env;

/// The error bound of one row's subexpressions.
#[derive(Debug)]
pub struct Bounds<'a> {
    /// The module of the expression.
    pub module: &'a Module,
    /// Its variant.
    pub env: &'a Env,
    /// The function's locals on this row.
    pub locals: &'a [Value],
}

/// An error bound: `None` when the value is indeterminate.
type Bound = Result<Option<f32>, String>;

const EPS: f32 = f32::EPSILON;

fn is_float(e: &Expr) -> bool {
    e.ty.scalar().is_some_and(|s| s.is_float())
}

/// Whether `e` is float arithmetic, or carries it unchanged (through constructors, swizzles,
/// indexing, negation and `select`): the compiler sees through those when it regroups.
fn arithmetic(e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Binary(op, ..) => matches!(op, BinOp::Add | BinOp::Sub | BinOp::Mul),
        ExprKind::Builtin(b, args) => {
            matches!(b.wgsl, "fma" | "dot") || (b.wgsl == "select" && args.iter().any(arithmetic))
        }
        ExprKind::Construct(args) => args.iter().any(arithmetic),
        ExprKind::Swizzle(x, _) | ExprKind::Index(x, _) | ExprKind::Unary(UnOp::Neg, x) => {
            arithmetic(x)
        }
        _ => false,
    }
}

fn product(e: &Expr) -> bool {
    matches!(e.kind, ExprKind::Binary(BinOp::Mul, ..))
}

fn approximate(name: &str) -> bool {
    matches!(
        name,
        "sqrt"
            | "sin"
            | "cos"
            | "exp"
            | "exp2"
            | "log"
            | "log2"
            | "inverseSqrt"
            | "radians"
            | "length"
            | "normalize"
            | "distance"
    )
}

impl Bounds<'_> {
    fn value(&self, e: &Expr) -> Result<Value, String> {
        eval_expr(self.module, self.env, e, self.locals).map_err(|e| e.to_string())
    }

    /// Largest magnitude of a float value's components (0 for non-floats).
    fn size(&self, e: &Expr) -> Result<f32, String> {
        Ok(self
            .value(e)?
            .components()
            .iter()
            .fold(0.0, |m, c| match c {
                Value::F32(x) => m.max(x.abs()),
                _ => m,
            }))
    }

    /// Float components of `e` (empty for non-floats).
    fn floats(&self, e: &Expr) -> Result<Vec<f32>, String> {
        Ok(self
            .value(e)?
            .components()
            .iter()
            .filter_map(|c| match c {
                Value::F32(x) => Some(*x),
                _ => None,
            })
            .collect())
    }

    /// The sum of the magnitudes of the terms a chain of `+`/`-` adds up (looking through
    /// negation, constructors, swizzles and indexing): what regrouping the chain can round.
    fn mass(&self, e: &Expr) -> Result<f32, String> {
        Ok(match &e.kind {
            ExprKind::Binary(BinOp::Add | BinOp::Sub, a, b) => self.mass(a)? + self.mass(b)?,
            ExprKind::Unary(UnOp::Neg, x) | ExprKind::Swizzle(x, _) | ExprKind::Index(x, _) => {
                self.mass(x)?
            }
            ExprKind::Construct(args) if args.iter().any(arithmetic) => {
                let mut m: f32 = 0.0;
                for a in args {
                    m = m.max(self.mass(a)?);
                }
                m
            }
            _ => self.size(e)?,
        })
    }

    /// Exact when every value in `x ± err` gives the same `f`.
    fn step(&self, x: &Expr, f: impl Fn(f32) -> f32) -> Bound {
        let Some(err) = self.err(x)? else {
            return Ok(None);
        };
        let same = self
            .floats(x)?
            .iter()
            .all(|v| f(v - err) == f(*v) && f(v + err) == f(*v));
        Ok(same.then_some(0.0))
    }

    /// The error bound of `e` on this row (0 for non-float values whose float operands are
    /// determinate), or `None` when the row's value of `e` is indeterminate.
    pub fn err(&self, e: &Expr) -> Bound {
        let children_max = |cs: &[&Expr]| -> Bound {
            let mut m: f32 = 0.0;
            for c in cs {
                match self.err(c)? {
                    Some(x) => m = m.max(x),
                    None => return Ok(None),
                }
            }
            Ok(Some(m))
        };
        match &e.kind {
            ExprKind::Lit(_)
            | ExprKind::Local(_)
            | ExprKind::Const(_)
            | ExprKind::Axis(_)
            | ExprKind::Global(_) => Ok(Some(0.0)),
            ExprKind::Binary(op, a, b) if is_float(a) => self.binary(*op, a, b),
            ExprKind::Cast(x) if is_float(x) && !is_float(e) => self.step(x, f32::trunc),
            // `v.as_ivec3()` is a conversion constructor: a cast per component.
            ExprKind::Construct(args) if !is_float(e) && args.iter().any(is_float) => {
                for a in args.iter().filter(|a| is_float(a)) {
                    if self.step(a, f32::trunc)?.is_none() {
                        return Ok(None);
                    }
                }
                Ok(Some(0.0))
            }
            ExprKind::Builtin(b, args) if args.iter().any(is_float) => self.builtin(b.wgsl, args),
            ExprKind::Unary(UnOp::Neg | UnOp::Not | UnOp::BitNot, x)
            | ExprKind::Cast(x)
            | ExprKind::Swizzle(x, _)
            | ExprKind::Field(x, _) => children_max(&[x]),
            ExprKind::Binary(_, a, b) | ExprKind::Index(a, b) => children_max(&[a, b]),
            ExprKind::Construct(args) | ExprKind::Builtin(_, args) | ExprKind::Call(_, args) => {
                children_max(&args.iter().collect::<Vec<_>>())
            }
            ExprKind::AddrOf(x) | ExprKind::Deref(x) => children_max(&[x]),
        }
    }

    fn binary(&self, op: BinOp, a: &Expr, b: &Expr) -> Bound {
        let (Some(ea), Some(eb)) = (self.err(a)?, self.err(b)?) else {
            return Ok(None);
        };
        let (sa, sb) = (self.size(a)?, self.size(b)?);
        let chained = arithmetic(a) || arithmetic(b);
        let inexact = ea + eb > 0.0;
        Ok(match op {
            // A chain may be summed in any order: each level adds a rounding of the chain's
            // whole mass (`(x + y) - y` may become `x + (y - y)`, or `100 + (x - floor(x))`
            // become `(100 + x) - floor(x)`).
            BinOp::Add | BinOp::Sub if chained => {
                Some(ea + eb + EPS * (self.mass(a)? + self.mass(b)?))
            }
            BinOp::Add | BinOp::Sub => Some(ea + eb + if inexact { EPS * (sa + sb) } else { 0.0 }),
            // Perturbed operands move the product, and its own rounding may then go either way;
            // a product of a chain may also be factored (`a*b + a*c` as `a*(b + c)`).
            BinOp::Mul => Some(
                sa * eb
                    + sb * ea
                    + ea * eb
                    + if inexact || product(a) || product(b) {
                        2.0 * EPS * sa * sb
                    } else {
                        0.0
                    },
            ),
            // `/` is approximate: its tolerance holds for exact operands only.
            BinOp::Div | BinOp::Rem => (ea == 0.0 && eb == 0.0).then_some(0.0),
            // A comparison is determinate when the operands are further apart than their errors.
            _ => {
                let (va, vb) = (self.floats(a)?, self.floats(b)?);
                let apart = va
                    .iter()
                    .zip(vb.iter().cycle())
                    .all(|(x, y)| (x - y).abs() > ea + eb);
                (apart || ea + eb == 0.0).then_some(0.0)
            }
        })
    }

    fn builtin(&self, name: &str, args: &[Expr]) -> Bound {
        let all: Vec<&Expr> = args.iter().collect();
        match (name, args) {
            ("floor", [x]) => self.step(x, f32::floor),
            ("ceil", [x]) => self.step(x, f32::ceil),
            ("trunc", [x]) => self.step(x, f32::trunc),
            // WGSL rounds halves to even; a half within the error is indeterminate either way.
            ("round", [x]) => self.step(x, |v| (v * 2.0).floor()),
            ("sign", [x]) => self.step(x, f32::signum),
            ("fract", [x]) => Ok(self.step(x, f32::floor)?.and(self.err(x)?)),
            ("step", [edge, x]) => {
                let ex = self.err(x)?;
                let ee = self.err(edge)?;
                let (Some(ex), Some(ee)) = (ex, ee) else {
                    return Ok(None);
                };
                let (vx, ve) = (self.floats(x)?, self.floats(edge)?);
                let apart = vx
                    .iter()
                    .zip(ve.iter().cycle())
                    .all(|(x, e)| (x - e).abs() > ex + ee);
                Ok((apart || ex + ee == 0.0).then_some(0.0))
            }
            ("fma" | "dot", [x, y, rest @ ..]) => {
                let (Some(ex), Some(ey)) = (self.err(x)?, self.err(y)?) else {
                    return Ok(None);
                };
                let (vx, vy) = (self.floats(x)?, self.floats(y)?);
                let products: f32 = vx
                    .iter()
                    .zip(vy.iter().cycle())
                    .map(|(a, b)| (a * b).abs())
                    .sum();
                let (sx, sy) = (self.size(x)?, self.size(y)?);
                let mut err =
                    EPS * products * 2.0 + vx.len() as f32 * (sx * ey + sy * ex + ex * ey);
                if let [z] = rest {
                    let Some(ez) = self.err(z)? else {
                        return Ok(None);
                    };
                    err += ez + EPS * self.size(z)?;
                }
                Ok(Some(err))
            }
            // `distance(a, b)` subtracts its arguments first: an argument that is itself
            // arithmetic can be regrouped with that subtraction.
            ("distance", _) if args.iter().any(arithmetic) => Ok(None),
            (n, _) if approximate(n) => {
                let exact = all.iter().try_fold(true, |ok, a| {
                    Ok::<_, String>(ok && self.err(a)? == Some(0.0))
                })?;
                Ok(exact.then_some(0.0))
            }
            _ => {
                let mut m: f32 = 0.0;
                for a in all {
                    match self.err(a)? {
                        Some(x) => m = m.max(x),
                        None => return Ok(None),
                    }
                }
                Ok(Some(m))
            }
        }
    }
}
