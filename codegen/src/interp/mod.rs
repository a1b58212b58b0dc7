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
//! - **Dispatches** ([`Dispatch`], `dispatch`): a compute entry point over a grid of
//!   workgroups, with storage and uniform buffers given as the bytes the GPU would get
//!   (`memory`), workgroup memory zeroed per workgroup, barriers, atomics, and subgroup
//!   operations (`sync`) at a subgroup size the caller picks, 4 to 128. A deterministic
//!   scheduler runs one invocation at a time to its next barrier or subgroup operation, in an
//!   order the caller picks, so a missing barrier is a wrong answer, not luck; invocations that
//!   do not reach a barrier together are a uniformity error with the source positions, and a
//!   subgroup operation runs over the lanes that reach it (its active lanes). A read or write
//!   of workgroup memory another invocation wrote since the last barrier is a data race error
//!   naming both places (`race`); with [`Dispatch::with_unwritten_read_check`], so is a read
//!   of workgroup memory no invocation of the workgroup wrote (an append that skipped a slot).
//!   Matrices (`matrix`) are columns of vectors.
//!   Textures are host texels (one mip level), loaded, stored and sampled through host
//!   samplers with bilinear filtering and depth comparison (`texture`).
//! - **Not yet**: pointers (`&mut` parameters), derivatives, vertex and
//!   fragment entry points, `determinant`. Each is an [`EvalError::Unsupported`] naming it.
//!
//! A kernel run on the host at subgroup size 8, its invocations in reverse order:
//!
//! ```
//! use codegen::interp::{Dispatch, Schedule};
//!
//! let c = codegen::compile_source(
//!     "#[shader(requires(subgroup))] mod m {
//!         #[storage(group = 0, binding = 0, read_write)]
//!         static OUT: [u32];
//!         #[compute(workgroup_size(16, 1, 1))]
//!         fn main(#[builtin(local_invocation_index)] lid: u32) {
//!             OUT[lid] = subgroup_exclusive_add(1u32);
//!         }
//!     }",
//! )?;
//! let mut d = Dispatch::new(&c.module, &c.keys[0].env, "main")?
//!     .with_subgroup_size(8)?
//!     .with_schedule(Schedule::Reversed);
//! d.set_buffer("OUT", &[0; 16 * 4])?;
//! d.run([1, 1, 1])?;
//! let out: Vec<u32> = d
//!     .buffer("OUT")?
//!     .chunks_exact(4)
//!     .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
//!     .collect();
//! assert_eq!(out, [0, 1, 2, 3, 4, 5, 6, 7, 0, 1, 2, 3, 4, 5, 6, 7]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
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
mod dispatch;
mod error;
mod exec;
mod expr;
mod matrix;
mod memory;
pub mod ops;
mod place;
mod race;
mod sync;
mod texture;
mod value;

#[cfg(test)]
mod dispatch_subgroup_tests;
#[cfg(test)]
mod dispatch_tests;
#[cfg(test)]
mod exec_tests;
#[cfg(test)]
mod tests;

pub use dispatch::{Dispatch, SUBGROUP_SIZES, Schedule};
pub use error::EvalError;
pub use exec::{DEFAULT_STEP_LIMIT, Machine};
pub use texture::{Address, Compare, HostSampler, HostTexture};
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
