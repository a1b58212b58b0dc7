//! Why an evaluation failed.

use std::fmt;

/// An expression the evaluator cannot or may not evaluate.
#[derive(Debug, Clone, PartialEq)]
pub enum EvalError {
    /// A construct the evaluator does not implement (resource access, textures, atomics,
    /// derivatives, subgroup operations, function calls, ..): the message names it.
    Unsupported(String),
    /// Operand values that do not fit the operation (an ill-typed IR, or a local that was
    /// given the wrong value): a bug in the caller or the front end.
    Type(String),
    /// A vector or array index outside the value (WGSL clamps or returns an indeterminate
    /// value; the evaluator refuses to guess).
    OutOfBounds {
        /// The index.
        index: i64,
        /// The number of elements.
        len: usize,
    },
    /// A local index beyond the `locals` slice given.
    UnknownLocal(usize),
    /// The [`super::Machine`]'s step limit was reached: a loop that does not end, or a run
    /// longer than the limit allows.
    StepLimit,
    /// Invocations of a dispatch that do not reach the same barrier or subgroup operation
    /// together (WGSL requires uniform control flow there): where each one is.
    Uniformity(String),
    /// Two invocations of a workgroup touched the same workgroup memory, one of them writing,
    /// with no barrier between: both places.
    Race(String),
    /// An invocation read workgroup memory that no invocation of its workgroup wrote (WGSL
    /// reads zero there; a kernel almost never means to), with
    /// [`super::Dispatch::with_unwritten_read_check`]: where.
    Unwritten(String),
    /// An error of one invocation of a dispatch.
    Invocation {
        /// `workgroup_id`.
        workgroup: [u32; 3],
        /// `local_invocation_index`.
        local: u32,
        /// What went wrong there.
        error: Box<EvalError>,
    },
    /// An error raised by the statement at this source position.
    At {
        /// 1-based line of the statement (in the file, or in the source string given to
        /// `compile_source`).
        line: usize,
        /// 1-based column.
        column: usize,
        /// What went wrong.
        error: Box<EvalError>,
    },
}

impl EvalError {
    /// This error located at `span`, unless it already has a location (the innermost
    /// statement wins).
    pub(crate) fn at(self, span: proc_macro2::Span) -> EvalError {
        match self {
            EvalError::At { .. } => self,
            error => {
                let start = span.start();
                EvalError::At {
                    line: start.line,
                    column: start.column + 1,
                    error: Box::new(error),
                }
            }
        }
    }

    /// The error without its location.
    pub fn cause(&self) -> &EvalError {
        match self {
            EvalError::At { error, .. } | EvalError::Invocation { error, .. } => error.cause(),
            e => e,
        }
    }
}

impl fmt::Display for EvalError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EvalError::Unsupported(what) => write!(f, "the evaluator does not support {what}"),
            EvalError::Type(what) => write!(f, "ill-typed evaluation: {what}"),
            EvalError::OutOfBounds { index, len } => {
                write!(f, "index {index} out of bounds for {len} elements")
            }
            EvalError::UnknownLocal(l) => write!(f, "local {l} has no value"),
            EvalError::StepLimit => {
                write!(f, "the step limit was reached (a loop that does not end?)")
            }
            EvalError::Uniformity(what) => write!(
                f,
                "non-uniform control flow at a barrier or subgroup operation: {what}"
            ),
            EvalError::Race(what) => write!(f, "data race on workgroup memory: {what}"),
            EvalError::Unwritten(what) => {
                write!(f, "read of unwritten workgroup memory: {what}")
            }
            EvalError::Invocation {
                workgroup,
                local,
                error,
            } => write!(f, "invocation {local} of workgroup {workgroup:?}: {error}"),
            EvalError::At {
                line,
                column,
                error,
            } => write!(f, "{error} (at {line}:{column})"),
        }
    }
}

impl std::error::Error for EvalError {}

pub(crate) fn type_err<T>(what: impl Into<String>) -> Result<T, EvalError> {
    Err(EvalError::Type(what.into()))
}
