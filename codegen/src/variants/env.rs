//! The axis environment of one variant.

use crate::ir::Lit;

/// Axis values of one variant, indexed like `Module::axes`.
#[derive(Debug, Clone, PartialEq)]
pub struct Env {
    /// One value per axis.
    pub values: Vec<Lit>,
}
