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
        }
    }
}

impl std::error::Error for EvalError {}

pub(crate) fn type_err<T>(what: impl Into<String>) -> Result<T, EvalError> {
    Err(EvalError::Type(what.into()))
}
