//! Variant axes: enumeration of the variant matrix, constraints, stable names, and
//! specialisation (constant evaluation of axis expressions, static pruning of `if`s,
//! reachability, capability checks).
//!
//! A variant is the module IR seen through an [`Env`] (one value per axis); this stage never
//! copies or rewrites the IR, and it never prints or validates anything.

mod env;
mod eval;
mod prune;

pub use env::Env;
pub use eval::{Value, eval};
pub use prune::{
    Branch, branch, check_capabilities, check_globals, entry_present, global_present, kept_globals,
    reachable_functions, used_globals,
};

use crate::ir::{Lit, Module};
use syn::{Error, Result};

/// One point of the variant matrix.
#[derive(Debug, Clone)]
pub struct Key {
    /// Axis values.
    pub env: Env,
    /// Stable name, e.g. `t16_msaa4_scalar`.
    pub name: String,
    /// Removed by an `exclude(..)` constraint.
    pub excluded: bool,
    /// Needs the SUBGROUP capability (`requires(subgroup = ..)`).
    pub subgroup: bool,
    /// Index of each axis value in its axis' value list.
    pub indices: Vec<usize>,
}

/// The stable name of a variant: axis labels and values joined by `_`.
///
/// Numeric axes give `label` + value (`t16`, `msaa4`, negative values as `m1`), except at the
/// axis' `unless` value, which gives nothing; boolean axes give their label when `true` and
/// nothing when `false`. With no fragments the name is `default`.
pub fn variant_name(m: &Module, env: &Env) -> String {
    let mut parts = vec![];
    for (axis, v) in m.axes.iter().zip(&env.values) {
        if axis.unnamed.as_ref() == Some(v) {
            continue;
        }
        match v {
            Lit::Bool(true) => parts.push(axis.label.clone()),
            Lit::Bool(false) => {}
            Lit::Int(i, _) if *i < 0 => parts.push(format!("{}m{}", axis.label, -i)),
            Lit::Int(i, _) => parts.push(format!("{}{i}", axis.label)),
            Lit::Float(..) => unreachable!("axes are integers or booleans"),
        }
    }
    if parts.is_empty() {
        "default".into()
    } else {
        parts.join("_")
    }
}

/// Enumerates every key of the matrix, in axis-major order (first axis varies slowest).
pub fn enumerate(m: &Module) -> Result<Vec<Key>> {
    let mut keys = vec![];
    let total: usize = m.axes.iter().map(|a| a.values.len()).product();
    for mut n in 0..total {
        let mut indices = vec![0; m.axes.len()];
        for (i, a) in m.axes.iter().enumerate().rev() {
            indices[i] = n % a.values.len();
            n /= a.values.len();
        }
        let env = Env {
            values: indices
                .iter()
                .zip(&m.axes)
                .map(|(&i, a)| a.values[i])
                .collect(),
        };
        let mut excluded = false;
        for e in &m.excludes {
            match eval(e, m, &env) {
                Some(Value::Bool(b)) => excluded |= b,
                _ => {
                    return Err(Error::new(
                        e.span,
                        "`exclude(..)` must be a constant predicate over axes",
                    ));
                }
            }
        }
        let subgroup = match &m.requires_subgroup {
            None => false,
            Some(e) => match eval(e, m, &env) {
                Some(Value::Bool(b)) => b,
                _ => {
                    return Err(Error::new(
                        e.span,
                        "`requires(subgroup = ..)` must be a constant predicate over axes",
                    ));
                }
            },
        };
        let name = variant_name(m, &env);
        keys.push(Key {
            env,
            name,
            excluded,
            subgroup,
            indices,
        });
    }
    if keys.iter().all(|k| k.excluded) {
        return Err(Error::new(
            m.span,
            "every variant is excluded by the `exclude(..)` constraints",
        ));
    }
    Ok(keys)
}
