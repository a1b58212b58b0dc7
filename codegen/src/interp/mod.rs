//! A host interpreter of the typed IR with the DSL's documented runtime semantics (WGSL's), the
//! reference the generated differential tests compare the GPU against.
//!
//! - **Expressions** ([`eval_expr`], `expr`): literals, locals, statics, consts, axes, unary and
//!   binary operators (with `&&`/`||` short-circuit), casts, swizzles, fields, indexing,
//!   constructors, the scalar/vector builtins of the language guide, and calls of module
//!   functions.
//! - **Statements** ([`Machine`], `exec`): `let`, assignment and compound assignment to locals,
//!   vector components, array elements, struct fields and statics (`place`), `if`, `for`,
//!   `while`, `loop`, `break`, `continue`, `return` and blocks, with a step limit so that a
//!   non-terminating loop is an error, not a hang. Errors raised by a statement carry its source
//!   line and column.
//! - **Not yet**: pointers (`&mut` parameters, atomics), textures, derivatives, subgroup
//!   operations, workgroup scheduling and barriers, matrices. Each is an
//!   [`EvalError::Unsupported`] naming it. Running a whole dispatch (invocations, workgroups,
//!   subgroups) is meant to be built on [`Machine`].
//!
//! The semantics are written from the WGSL specification's rules, independently of the
//! printer: see [`ops`] for integer overflow, shifts, division by zero and float-to-int
//! conversion, and [`builtins`] for the functions. A `for` loop's end is evaluated once, as in
//! Rust (the front end hoists it), and `a..=b` stops after `b` even when `b` is the type's
//! maximum.
//!
//! Abstract literals (unsuffixed `1`, `0.5`) take the concrete type their context gives them,
//! as WGSL's automatic conversions do: the evaluator passes the expected scalar down into
//! abstract-typed subexpressions.

pub mod builtins;
mod error;
mod exec;
mod expr;
pub mod ops;
mod place;
mod value;

#[cfg(test)]
mod exec_tests;
#[cfg(test)]
mod tests;

pub use error::EvalError;
pub use exec::{DEFAULT_STEP_LIMIT, Machine};
pub use value::Value;

use crate::ir::{Expr, Module};
use crate::variants::Env;

/// Evaluates `expr`, an expression of a function of `module`, in the variant `env`, with
/// `locals[i]` the value of the function's local `i` (`Function::locals` order: parameters
/// first). Locals the expression does not read may hold anything. Statics have no value here:
/// use a [`Machine`] to give them one.
pub fn eval_expr(
    module: &Module,
    env: &Env,
    expr: &Expr,
    locals: &[Value],
) -> Result<Value, EvalError> {
    Machine::new(module, env).eval(locals, expr, None)
}
