//! What one invocation of a [`super::Dispatch`] and its scheduler say to each other, and the
//! subgroup collectives the scheduler computes once every lane of a subgroup has arrived.
//!
//! Invocations are coroutines on the scheduler's thread, and only one runs at a time: the
//! running one owns the statics (storage buffers and workgroup memory) and hands them back at
//! each barrier, subgroup operation or at its end.

use super::error::EvalError;
use super::value::{Value, scalar_from_f64};
use super::{builtins, ops};
use crate::ir::BinOp;

/// The statics, passed from invocation to invocation.
pub(crate) type Globals = Vec<Option<Value>>;

/// What an invocation waits for.
#[derive(Debug, Clone)]
pub(crate) enum SyncOp {
    /// `workgroupBarrier` or `storageBarrier`: every invocation of the workgroup.
    Barrier(&'static str),
    /// A subgroup builtin (WGSL name) with this lane's arguments: every lane of the subgroup.
    Subgroup {
        wgsl: &'static str,
        args: Vec<Value>,
    },
}

impl SyncOp {
    /// The WGSL name, for messages.
    pub fn name(&self) -> &'static str {
        match self {
            SyncOp::Barrier(n) | SyncOp::Subgroup { wgsl: n, .. } => n,
        }
    }
}

/// An invocation waiting at a synchronisation point of the source.
#[derive(Debug, Clone)]
pub(crate) struct Arrival {
    pub op: SyncOp,
    pub line: usize,
    pub column: usize,
}

impl Arrival {
    /// Whether two arrivals are at the same point of the source with the same operation.
    pub fn same_site(&self, other: &Arrival) -> bool {
        (self.line, self.column, self.op.name()) == (other.line, other.column, other.op.name())
    }

    /// `workgroupBarrier at 12:9`.
    pub fn describe(&self) -> String {
        format!("{} at {}:{}", self.op.name(), self.line, self.column)
    }
}

/// From the scheduler to an invocation it resumes: the statics, and the result of the subgroup
/// operation the invocation waited at.
pub(crate) struct Resume {
    pub globals: Globals,
    pub result: Option<Value>,
}

/// What an invocation hands back when it suspends: where it waits, and the statics.
pub(crate) type Suspended = (Arrival, Globals);

/// What an invocation hands back when it returns: its result, and the statics.
pub(crate) type Finished = (Result<(), EvalError>, Globals);

/// The handle an invocation suspends itself with.
pub(crate) type Yielder = corosensei::Yielder<Resume, Suspended>;

/// A value shaped like `v` (scalar or vector) with every component `x`.
fn filled_like(v: &Value, x: f64) -> Value {
    match v {
        Value::Vector(c) => Value::Vector(c.iter().map(|e| filled_like(e, x)).collect()),
        v => v
            .scalar()
            .map_or(Value::F32(x as f32), |s| scalar_from_f64(s, x)),
    }
}

fn reduce(
    values: &[&Value],
    mut f: impl FnMut(&Value, &Value) -> Result<Value, EvalError>,
) -> Result<Value, EvalError> {
    let (first, rest) = values
        .split_first()
        .ok_or_else(|| EvalError::Type("a subgroup operation with no lane".into()))?;
    rest.iter().try_fold((*first).clone(), |acc, v| f(&acc, v))
}

fn boolean(v: &Value) -> Result<bool, EvalError> {
    match v {
        Value::Bool(b) => Ok(*b),
        v => Err(EvalError::Type(format!("a bool expected, found {v}"))),
    }
}

/// The results of the subgroup operation `wgsl` for the active lanes of one subgroup, given
/// each active lane's index in the subgroup and its arguments, in lane order (sums are
/// accumulated in lane order; a ballot sets the bits of the active lanes' indices).
pub(crate) fn collective(wgsl: &str, lanes: &[(usize, &[Value])]) -> Result<Vec<Value>, EvalError> {
    let args: Vec<&[Value]> = lanes.iter().map(|(_, a)| *a).collect();
    let lanes_n = lanes.len();
    let first_arg = |k: usize| -> Result<&Value, EvalError> {
        args[k]
            .first()
            .ok_or_else(|| EvalError::Type(format!("`{wgsl}` without an argument")))
    };
    let x: Vec<&Value> = (0..lanes_n).map(first_arg).collect::<Result<_, _>>()?;
    let same = |v: Value| Ok(vec![v; lanes_n]);
    let binop = |op| move |a: &Value, b: &Value| ops::binary(op, a, b);
    match wgsl {
        "subgroupBallot" => {
            let mut words = [0u32; 4];
            for ((lane, _), v) in lanes.iter().zip(&x) {
                if boolean(v)? {
                    words[lane / 32] |= 1 << (lane % 32);
                }
            }
            same(Value::Vector(
                words.iter().map(|w| Value::U32(*w)).collect(),
            ))
        }
        "subgroupAll" | "subgroupAny" => {
            let bits = x
                .iter()
                .map(|v| boolean(v))
                .collect::<Result<Vec<_>, _>>()?;
            let r = if wgsl == "subgroupAll" {
                bits.iter().all(|b| *b)
            } else {
                bits.iter().any(|b| *b)
            };
            same(Value::Bool(r))
        }
        "subgroupAdd" => same(reduce(&x, binop(BinOp::Add))?),
        "subgroupMul" => same(reduce(&x, binop(BinOp::Mul))?),
        "subgroupAnd" => same(reduce(&x, binop(BinOp::BitAnd))?),
        "subgroupOr" => same(reduce(&x, binop(BinOp::BitOr))?),
        "subgroupXor" => same(reduce(&x, binop(BinOp::BitXor))?),
        "subgroupMin" | "subgroupMax" => {
            let name = if wgsl == "subgroupMin" { "min" } else { "max" };
            same(reduce(&x, |a, b| {
                builtins::call(name, &[a.clone(), b.clone()])
            })?)
        }
        "subgroupExclusiveAdd"
        | "subgroupInclusiveAdd"
        | "subgroupExclusiveMul"
        | "subgroupInclusiveMul" => {
            let (op, identity) = if wgsl.ends_with("Add") {
                (BinOp::Add, 0.0)
            } else {
                (BinOp::Mul, 1.0)
            };
            let inclusive = wgsl.contains("Inclusive");
            let mut acc = filled_like(x[0], identity);
            let mut out = Vec::with_capacity(lanes_n);
            for v in &x {
                let next = ops::binary(op, &acc, v)?;
                out.push(if inclusive { next.clone() } else { acc });
                acc = next;
            }
            Ok(out)
        }
        "subgroupBroadcastFirst" => same(x[0].clone()),
        "subgroupShuffle" | "subgroupBroadcast" => (0..lanes_n)
            .map(|k| {
                let lane = match args[k].get(1) {
                    Some(Value::U32(l)) => i64::from(*l),
                    Some(Value::I32(l)) => i64::from(*l),
                    other => {
                        return Err(EvalError::Type(format!("`{wgsl}` lane {other:?}")));
                    }
                };
                // Reading an inactive or missing lane is indeterminate in WGSL: an error here.
                lanes
                    .iter()
                    .position(|(l, _)| i64::try_from(*l).ok() == Some(lane))
                    .map(|at| x[at].clone())
                    .ok_or_else(|| {
                        EvalError::Unsupported(format!(
                            "`{wgsl}` reading lane {lane}, which is not active here"
                        ))
                    })
            })
            .collect(),
        other => Err(EvalError::Unsupported(format!(
            "the subgroup operation `{other}`"
        ))),
    }
}
