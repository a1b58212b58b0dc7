//! Random statement programs: state variables (integer and `bool` scalars, integer vectors,
//! `[T; 4]` arrays) changed by nested `if`/`else`, bounded `while`, `loop` and `for` loops
//! (exclusive, inclusive, ending at the type's maximum, with an end the body changes), guarded
//! `break` and `continue`, shadowing `let`s, and assignment and compound assignment to whole
//! variables, vector components (by name and by runtime index) and array elements. Every loop
//! ends by construction. Expressions come from the expression generator, with some input
//! leaves rebound to the variables in scope.
//!
//! This module holds the program tree and its shrinking; generation is in
//! [`super::program_gen`], the DSL text in [`super::program_text`].
//!
//! Programs compute on integers and `bool`s only (no float reads either): a float comparison
//! within the driver's regrouping error could send the GPU down the other branch (see the
//! guide's Semantics section), and whole programs have no error bound. Floats are the
//! expression test's job, row by row with [`super::bound`].

use super::ast::{E, Sc, T};
pub use super::program_gen::program;

/// The shape of a state variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// A scalar or vector of type `T`.
    Value(T),
    /// `[s; 4]`.
    Array(Sc),
}

impl Shape {
    /// 32-bit output words.
    pub fn words(self) -> usize {
        match self {
            Shape::Value(t) => t.n as usize,
            Shape::Array(_) => ARRAY_LEN,
        }
    }

    /// The scalar type.
    pub fn scalar(self) -> Sc {
        match self {
            Shape::Value(t) => t.s,
            Shape::Array(s) => s,
        }
    }

    /// The DSL spelling (`IVec3`, `[u32; 4]`).
    pub fn name(self) -> String {
        match self {
            Shape::Value(t) => t.name(),
            Shape::Array(s) => format!("[{}; {ARRAY_LEN}]", s.name()),
        }
    }
}

/// Elements of array state.
pub const ARRAY_LEN: usize = 4;

/// An assignment target.
#[derive(Debug, Clone, PartialEq)]
pub enum Place {
    /// The whole variable.
    Whole(String),
    /// `v.y`
    Component(String, char),
    /// `v[(i % n)]` / `a[(i % 4)]` with `i: u32`.
    Indexed(String, usize, E),
}

/// A statement.
#[derive(Debug, Clone, PartialEq)]
pub enum St {
    /// `place op= value` (`op` empty for plain assignment).
    Assign(Place, &'static str, E),
    /// `let [mut] name: T = value;` shadowing a state variable for the rest of its block.
    Let(String, bool, Shape, E),
    /// `if c { .. } [else { .. }]`
    If(E, Vec<St>, Option<Vec<St>>),
    /// `let mut c = 0u32; while c < bound && cond { c += 1u32; body }`
    While(String, u32, E, Vec<St>),
    /// `let mut c = 0u32; loop { c += 1u32; if c > bound { break; } body }`
    Loop(String, u32, Vec<St>),
    /// `for var in start..end` or `..=end`, over `ty`.
    For(String, Sc, E, E, bool, Vec<St>),
    /// `if c { break; }`
    BreakIf(E),
    /// `if c { continue; }`
    ContinueIf(E),
    /// `{ .. }`
    Block(Vec<St>),
}

/// One program: its state variables and its body.
#[derive(Debug, Clone, PartialEq)]
pub struct Program {
    /// State variables: name, shape, initial value (array elements for arrays).
    pub vars: Vec<(String, Shape, Vec<E>)>,
    /// Statements.
    pub body: Vec<St>,
}

impl Program {
    /// Output words.
    pub fn words(&self) -> usize {
        self.vars.iter().map(|v| v.1.words()).sum()
    }

    /// Statements, counted through nested blocks.
    pub fn size(&self) -> usize {
        fn count(b: &[St]) -> usize {
            b.iter()
                .map(|s| 1 + children(s).iter().map(|c| count(c)).sum::<usize>())
                .sum()
        }
        count(&self.body)
    }
}

/// The statement's bodies.
pub fn children(s: &St) -> Vec<&Vec<St>> {
    match s {
        St::If(_, t, e) => std::iter::once(t).chain(e.as_ref()).collect(),
        St::While(.., b) | St::Loop(.., b) | St::For(.., b) | St::Block(b) => vec![b],
        _ => vec![],
    }
}

/// Smaller programs: one statement removed, or a compound statement replaced by its body;
/// smallest first.
pub fn shrink_candidates(p: &Program) -> Vec<Program> {
    let n = p.size();
    let mut out = vec![];
    for at in 0..n {
        for how in 0..3 {
            let mut q = p.clone();
            let mut k = at;
            if edit(&mut q.body, &mut k, how) && q.size() < n {
                out.push(q);
            }
        }
    }
    out.sort_by_key(Program::size);
    out.dedup();
    out
}

/// Applies edit `how` to the statement at pre-order position `*k`: 0 removes it, 1 replaces
/// it by its (first) body, 2 by its `else` body.
fn edit(b: &mut Vec<St>, k: &mut usize, how: usize) -> bool {
    for i in 0..b.len() {
        if *k == 0 {
            let bodies: Vec<Vec<St>> = children(&b[i]).into_iter().cloned().collect();
            let replacement = match how {
                0 => vec![],
                1 if !bodies.is_empty() => bodies[0].clone(),
                2 if bodies.len() > 1 => bodies[1].clone(),
                _ => return false,
            };
            b.splice(i..=i, replacement);
            return true;
        }
        *k -= 1;
        let found = match &mut b[i] {
            St::If(_, t, e) => edit(t, k, how) || e.as_mut().is_some_and(|e| edit(e, k, how)),
            St::While(.., body) | St::Loop(.., body) | St::For(.., body) | St::Block(body) => {
                edit(body, k, how)
            }
            _ => false,
        };
        if found {
            return true;
        }
    }
    false
}
