//! Statement execution: the [`Machine`] runs a module function's body over a frame of locals,
//! with the statics the host gave values to, and a step limit.

use super::error::EvalError;
use super::ops;
use super::sync::{Arrival, SyncOp};
use super::value::Value;
use crate::ir::{BinOp, Block, Expr, Function, Module, Scalar, Stmt};
use crate::variants::Env;
use proc_macro2::Span;

/// Statements a [`Machine`] executes before it stops with [`EvalError::StepLimit`], unless
/// [`Machine::with_step_limit`] says otherwise.
pub const DEFAULT_STEP_LIMIT: u64 = 10_000_000;

/// Runs functions of one module in one variant: one invocation, on the host.
///
/// ```
/// # use codegen::interp::{Machine, Value};
/// let c = codegen::compile_source(
///     "#[shader] mod m {
///         fn tri(n: u32) -> u32 { let mut s = 0u32; for i in 1..=n { s += i; } s }
///         #[compute(workgroup_size(1, 1, 1))] fn main() {}
///     }",
/// )
/// .unwrap();
/// let mut m = Machine::new(&c.module, &c.keys[0].env);
/// assert_eq!(m.run("tri", vec![Value::U32(4)]).unwrap(), Some(Value::U32(10)));
/// ```
pub struct Machine<'a> {
    pub(crate) module: &'a Module,
    pub(crate) env: &'a Env,
    pub(crate) globals: Vec<Option<Value>>,
    steps_left: u64,
    /// Set when the machine runs one invocation of a [`super::Dispatch`]: barriers and subgroup
    /// operations wait for the other invocations there.
    pub(crate) yielder: Option<&'a super::sync::Yielder>,
    /// Set when the machine runs one invocation of a [`super::Dispatch`] that checks workgroup
    /// memory for data races: the workgroup's tracker and this invocation's index.
    pub(crate) race: Option<(std::rc::Rc<std::cell::RefCell<super::race::Tracker>>, u32)>,
}

impl std::fmt::Debug for Machine<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Machine")
            .field("module", &self.module.name)
            .field("steps_left", &self.steps_left)
            .finish_non_exhaustive()
    }
}

/// How a statement ended.
enum Flow {
    Next,
    Break,
    Continue,
    Return(Option<Value>),
}

impl<'a> Machine<'a> {
    /// A machine for `module` in the variant `env`, with no static given a value yet.
    pub fn new(module: &'a Module, env: &'a Env) -> Machine<'a> {
        Machine {
            module,
            env,
            globals: vec![None; module.globals.len()],
            steps_left: DEFAULT_STEP_LIMIT,
            yielder: None,
            race: None,
        }
    }

    /// Stops with [`EvalError::StepLimit`] after `steps` more statements or loop iterations.
    pub fn with_step_limit(mut self, steps: u64) -> Machine<'a> {
        self.steps_left = steps;
        self
    }

    /// Gives the static `name` (a buffer, uniform or private/workgroup variable) a value: a
    /// [`Value::Array`] for `[T]` and `[T; N]`, a [`Value::Struct`] for a struct.
    pub fn set_global(&mut self, name: &str, value: Value) -> Result<(), EvalError> {
        let g = self.global_index(name)?;
        self.globals[g] = Some(value);
        Ok(())
    }

    /// The current value of the static `name`, if it has one.
    pub fn global_value(&self, name: &str) -> Option<&Value> {
        let g = self.global_index(name).ok()?;
        self.globals[g].as_ref()
    }

    fn global_index(&self, name: &str) -> Result<usize, EvalError> {
        self.module
            .globals
            .iter()
            .position(|g| g.name == name)
            .ok_or_else(|| EvalError::Type(format!("the module has no static `{name}`")))
    }

    pub(crate) fn global(&self, g: usize) -> Result<&Value, EvalError> {
        self.globals[g].as_ref().ok_or_else(|| self.no_value(g))
    }

    #[expect(
        clippy::expect_used,
        reason = "checked for a value first: returning the borrow from a match would not pass the borrow checker"
    )]
    pub(crate) fn global_mut(&mut self, g: usize) -> Result<&mut Value, EvalError> {
        if self.globals[g].is_none() {
            return Err(self.no_value(g));
        }
        Ok(self.globals[g].as_mut().expect("checked above"))
    }

    fn no_value(&self, g: usize) -> EvalError {
        EvalError::Unsupported(format!(
            "reading the static `{}` before the host gave it a value (Machine::set_global)",
            self.module.globals[g].name
        ))
    }

    /// Runs the function `name` with `args` (one per parameter, entry point builtins
    /// included); its return value, `None` for a function without one.
    pub fn run(&mut self, name: &str, args: Vec<Value>) -> Result<Option<Value>, EvalError> {
        let f = self
            .module
            .functions
            .iter()
            .position(|f| f.name == name)
            .ok_or_else(|| EvalError::Type(format!("the module has no function `{name}`")))?;
        self.call(f, args)
    }

    pub(crate) fn call(&mut self, f: usize, args: Vec<Value>) -> Result<Option<Value>, EvalError> {
        let module = self.module;
        let func = &module.functions[f];
        if args.len() != func.params.len() {
            return Err(EvalError::Type(format!(
                "`{}` takes {} arguments, given {}",
                func.name,
                func.params.len(),
                args.len()
            )));
        }
        let mut frame = vec![Value::Bool(false); func.locals.len()];
        for (p, a) in func.params.iter().zip(args) {
            frame[p.local] = a;
        }
        match self.block(func, &mut frame, &func.body)? {
            Flow::Return(v) => Ok(v),
            _ => Ok(None),
        }
    }

    /// Waits at a barrier or subgroup operation (at `span`) until the dispatch's scheduler
    /// resumes this invocation; the subgroup operation's result. A machine outside a dispatch
    /// has no other invocation to wait for: that is an error naming the operation.
    pub(crate) fn sync(&mut self, op: SyncOp, span: Span) -> Result<Option<Value>, EvalError> {
        let Some(yielder) = self.yielder else {
            return Err(EvalError::Unsupported(format!(
                "`{}` outside a dispatch (run the entry point with interp::Dispatch)",
                op.name()
            )));
        };
        let start = span.start();
        let at = Arrival {
            op,
            line: start.line,
            column: start.column + 1,
        };
        let globals = std::mem::take(&mut self.globals);
        let resume = yielder.suspend((at, globals));
        self.globals = resume.globals;
        Ok(resume.result)
    }

    fn step(&mut self) -> Result<(), EvalError> {
        if self.steps_left == 0 {
            return Err(EvalError::StepLimit);
        }
        self.steps_left -= 1;
        Ok(())
    }

    fn block(&mut self, f: &Function, frame: &mut [Value], b: &Block) -> Result<Flow, EvalError> {
        for s in b {
            match self.stmt(f, frame, s).map_err(|e| e.at(stmt_span(s)))? {
                Flow::Next => {}
                flow => return Ok(flow),
            }
        }
        Ok(Flow::Next)
    }

    fn stmt(&mut self, f: &Function, frame: &mut [Value], s: &Stmt) -> Result<Flow, EvalError> {
        self.step()?;
        match s {
            Stmt::Let { local, init, .. } => {
                let want = local.and_then(|l| f.locals[l].ty.scalar());
                let v = self.eval(frame, init, want)?;
                if let Some(l) = local {
                    frame[*l] = v;
                }
            }
            Stmt::Assign {
                place, op, value, ..
            } => self.assign(frame, place, *op, value)?,
            Stmt::Expr(e) => {
                self.eval(frame, e, None)?;
            }
            Stmt::If {
                cond, then, els, ..
            } => {
                if self.condition(frame, cond)? {
                    return self.block(f, frame, then);
                } else if let Some(els) = els {
                    return self.block(f, frame, els);
                }
            }
            Stmt::For {
                var,
                start,
                end,
                inclusive,
                body,
                ..
            } => return self.for_loop(f, frame, *var, (start, end, *inclusive), body),
            Stmt::While { cond, body, .. } => loop {
                self.step()?;
                if !self.condition(frame, cond)? {
                    break;
                }
                match self.block(f, frame, body)? {
                    Flow::Break => break,
                    Flow::Return(v) => return Ok(Flow::Return(v)),
                    Flow::Next | Flow::Continue => {}
                }
            },
            Stmt::Loop { body, .. } => loop {
                self.step()?;
                match self.block(f, frame, body)? {
                    Flow::Break => break,
                    Flow::Return(v) => return Ok(Flow::Return(v)),
                    Flow::Next | Flow::Continue => {}
                }
            },
            Stmt::Break(_) => return Ok(Flow::Break),
            Stmt::Continue(_) => return Ok(Flow::Continue),
            Stmt::Return(e, _) => {
                let v = match e {
                    Some(e) => Some(self.eval(frame, e, f.ret.scalar())?),
                    None => None,
                };
                return Ok(Flow::Return(v));
            }
            Stmt::Discard(_) => return Err(EvalError::Unsupported("`discard()`".into())),
            Stmt::Block(b) => return self.block(f, frame, b),
        }
        Ok(Flow::Next)
    }

    fn condition(&mut self, frame: &[Value], cond: &Expr) -> Result<bool, EvalError> {
        match self.eval(frame, cond, None)? {
            Value::Bool(b) => Ok(b),
            v => Err(EvalError::Type(format!("condition {v}"))),
        }
    }

    fn assign(
        &mut self,
        frame: &mut [Value],
        place: &Expr,
        op: Option<BinOp>,
        value: &Expr,
    ) -> Result<(), EvalError> {
        let want = match op {
            Some(BinOp::Shl | BinOp::Shr) => Some(Scalar::U32),
            _ => place.ty.scalar(),
        };
        let mut v = self.eval(frame, value, want)?;
        if let Some(op) = op {
            let old = self.eval(frame, place, None)?;
            v = ops::binary(op, &old, &v)?;
        }
        self.store(frame, place, v)
    }

    /// `for var in start..end` (or `..=`): `start` and `end` evaluated once, as in Rust.
    fn for_loop(
        &mut self,
        f: &Function,
        frame: &mut [Value],
        var: usize,
        (start, end, inclusive): (&Expr, &Expr, bool),
        body: &Block,
    ) -> Result<Flow, EvalError> {
        let s = f.locals[var].ty.scalar();
        let first = int(&self.eval(frame, start, s)?)?;
        let last = int(&self.eval(frame, end, s)?)?;
        let last = if inclusive { last } else { last - 1 };
        let mut i = first;
        while i <= last {
            self.step()?;
            frame[var] = match s {
                Some(Scalar::U32) => Value::U32(i as u32),
                _ => Value::I32(i as i32),
            };
            match self.block(f, frame, body)? {
                Flow::Break => break,
                Flow::Return(v) => return Ok(Flow::Return(v)),
                Flow::Next | Flow::Continue => {}
            }
            i += 1;
        }
        Ok(Flow::Next)
    }
}

fn int(v: &Value) -> Result<i64, EvalError> {
    match v {
        Value::I32(i) => Ok(*i as i64),
        Value::U32(u) => Ok(*u as i64),
        v => Err(EvalError::Type(format!("loop bound {v}"))),
    }
}

fn stmt_span(s: &Stmt) -> Span {
    match s {
        Stmt::Let { span, .. }
        | Stmt::Assign { span, .. }
        | Stmt::If { span, .. }
        | Stmt::For { span, .. }
        | Stmt::While { span, .. }
        | Stmt::Loop { span, .. }
        | Stmt::Break(span)
        | Stmt::Continue(span)
        | Stmt::Return(_, span)
        | Stmt::Discard(span) => *span,
        Stmt::Expr(e) => e.span,
        Stmt::Block(b) => b.first().map_or_else(Span::call_site, stmt_span),
    }
}
