//! Static pruning: which `if` branches, functions and globals a variant keeps, and whether the
//! code it keeps needs a capability the variant did not declare.

use super::{Env, Value, eval};
use crate::ir::{Block, Expr, ExprKind, Io, Module, Stmt};
use proc_macro2::Span;
use syn::{Error, Result};

/// How an `if` behaves in one variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Branch {
    /// The condition is constant `true`: only the then-branch is kept.
    Then,
    /// The condition is constant `false`: only the else-branch (if any) is kept.
    Else,
    /// Decided at run time.
    Dynamic,
}

/// Decides an `if` condition for a variant.
pub fn branch(cond: &Expr, m: &Module, env: &Env) -> Branch {
    match eval(cond, m, env) {
        Some(Value::Bool(true)) => Branch::Then,
        Some(Value::Bool(false)) => Branch::Else,
        _ => Branch::Dynamic,
    }
}

fn walk_expr(e: &Expr, f: &mut dyn FnMut(&Expr)) {
    f(e);
    match &e.kind {
        ExprKind::Unary(_, x)
        | ExprKind::Cast(x)
        | ExprKind::Field(x, _)
        | ExprKind::Swizzle(x, _) => walk_expr(x, f),
        ExprKind::AddrOf(x) | ExprKind::Deref(x) => walk_expr(x, f),
        ExprKind::Binary(_, a, b) | ExprKind::Index(a, b) => {
            walk_expr(a, f);
            walk_expr(b, f);
        }
        ExprKind::Construct(args) | ExprKind::Call(_, args) | ExprKind::Builtin(_, args) => {
            args.iter().for_each(|a| walk_expr(a, f));
        }
        ExprKind::Lit(_)
        | ExprKind::Local(_)
        | ExprKind::Global(_)
        | ExprKind::Const(_)
        | ExprKind::Axis(_) => {}
    }
}

/// Visits every expression of the code a variant keeps.
pub(crate) fn walk_block(b: &Block, m: &Module, env: &Env, f: &mut dyn FnMut(&Expr)) {
    for s in b {
        match s {
            Stmt::Let { init, .. } => walk_expr(init, f),
            Stmt::Assign { place, value, .. } => {
                walk_expr(place, f);
                walk_expr(value, f);
            }
            Stmt::Expr(e) => walk_expr(e, f),
            Stmt::Return(e, _) => {
                if let Some(e) = e {
                    walk_expr(e, f);
                }
            }
            Stmt::If {
                cond, then, els, ..
            } => match branch(cond, m, env) {
                Branch::Then => walk_block(then, m, env, f),
                Branch::Else => {
                    if let Some(e) = els {
                        walk_block(e, m, env, f);
                    }
                }
                Branch::Dynamic => {
                    walk_expr(cond, f);
                    walk_block(then, m, env, f);
                    if let Some(e) = els {
                        walk_block(e, m, env, f);
                    }
                }
            },
            Stmt::For {
                start, end, body, ..
            } => {
                walk_expr(start, f);
                walk_expr(end, f);
                walk_block(body, m, env, f);
            }
            Stmt::While { cond, body, .. } => {
                walk_expr(cond, f);
                walk_block(body, m, env, f);
            }
            Stmt::Loop { body, .. } | Stmt::Block(body) => walk_block(body, m, env, f),
            Stmt::Break(_) | Stmt::Continue(_) | Stmt::Discard(_) => {}
        }
    }
}

/// Whether function `f` is an entry point of this variant: it has a stage and its
/// `#[when(..)]` holds (or it has none).
pub fn entry_present(f: &crate::ir::Function, m: &Module, env: &Env) -> bool {
    f.stage.is_some()
        && f.when
            .as_ref()
            .is_none_or(|w| eval(w, m, env) == Some(Value::Bool(true)))
}

/// Functions reachable from the given roots (default: the variant's entry points) in this
/// variant.
pub fn reachable_functions(m: &Module, env: &Env, roots: Option<&[usize]>) -> Vec<bool> {
    let mut seen = vec![false; m.functions.len()];
    let mut stack: Vec<usize> = match roots {
        Some(r) => r.to_vec(),
        None => (0..m.functions.len())
            .filter(|&i| m.library || entry_present(&m.functions[i], m, env))
            .collect(),
    };
    while let Some(fi) = stack.pop() {
        if std::mem::replace(&mut seen[fi], true) {
            continue;
        }
        walk_block(&m.functions[fi].body, m, env, &mut |e| {
            if let ExprKind::Call(callee, _) = e.kind {
                stack.push(callee);
            }
        });
    }
    seen
}

/// Globals used (transitively) by one entry point in this variant.
pub fn used_globals(m: &Module, env: &Env, entry: usize) -> Vec<bool> {
    let fns = reachable_functions(m, env, Some(&[entry]));
    let mut used = vec![false; m.globals.len()];
    for (fi, keep) in fns.iter().enumerate() {
        if *keep {
            walk_block(&m.functions[fi].body, m, env, &mut |e| {
                if let ExprKind::Global(g) = e.kind {
                    used[g] = true;
                }
            });
        }
    }
    used
}

/// Which statics a variant emits and reflects: those present ([`global_present`]), except
/// the bindings merged from a library into a bind group that no entry point of the module
/// uses in this variant: a library's group costs a variant nothing it does not read (a masked
/// pass's material group is not in its opaque variant's layout), while a group the variant
/// does use keeps every binding, as the host binds it. A library compiled on its own keeps
/// everything, as it keeps every function.
pub fn kept_globals(m: &Module, env: &Env) -> Vec<bool> {
    let present: Vec<bool> = m
        .globals
        .iter()
        .map(|g| global_present(g, m, env))
        .collect();
    let has_entries = m.functions.iter().any(|f| entry_present(f, m, env));
    if m.library || !has_entries || !m.globals.iter().any(|g| g.from_library) {
        return present;
    }
    let mut used_groups = std::collections::BTreeSet::new();
    for (i, f) in m.functions.iter().enumerate() {
        if entry_present(f, m, env) {
            for (g, used) in used_globals(m, env, i).into_iter().enumerate() {
                if let (true, Some((group, _))) = (used, m.globals[g].binding) {
                    used_groups.insert(group);
                }
            }
        }
    }
    m.globals
        .iter()
        .zip(present)
        .map(|(g, present)| {
            let unused_library_group = g.from_library
                && g.binding
                    .is_some_and(|(group, _)| !used_groups.contains(&group));
            present && !unused_library_group
        })
        .collect()
}

/// Whether a `static` exists in this variant (its `#[when(..)]` holds, or it has none).
pub fn global_present(g: &crate::ir::Global, m: &Module, env: &Env) -> bool {
    g.when
        .as_ref()
        .is_none_or(|w| eval(w, m, env) == Some(Value::Bool(true)))
}

/// Checks the statics of a variant: no two present ones share a binding, and kept code uses
/// only present ones.
pub fn check_globals(m: &Module, env: &Env, variant: &str) -> Result<()> {
    let present: Vec<bool> = m
        .globals
        .iter()
        .map(|g| global_present(g, m, env))
        .collect();
    for (i, g) in m.globals.iter().enumerate() {
        if !present[i] || g.binding.is_none() {
            continue;
        }
        if let Some(other) = m.globals[..i]
            .iter()
            .enumerate()
            .find(|(j, o)| present[*j] && o.binding == g.binding)
        {
            let (group, binding) = g.binding.unwrap_or_default();
            return Err(Error::new(
                g.span,
                format!(
                    "binding conflict in variant `{variant}`: `group = {group}, binding = {binding}` is also used by `{}`",
                    other.1.name
                ),
            ));
        }
    }
    let reach = reachable_functions(m, env, None);
    let mut bad: Option<(Span, usize)> = None;
    for (fi, keep) in reach.iter().enumerate() {
        if *keep {
            walk_block(&m.functions[fi].body, m, env, &mut |e| {
                if let ExprKind::Global(g) = e.kind
                    && !present[g]
                    && bad.is_none()
                {
                    bad = Some((e.span, g));
                }
            });
        }
    }
    match bad {
        None => Ok(()),
        Some((span, g)) => Err(Error::new(
            span,
            format!(
                "`{}` does not exist in variant `{variant}` (its `#[when(..)]` is false there); guard this use with an `if` on the same axes",
                m.globals[g].name
            ),
        )),
    }
}

/// Fails at the first subgroup operation kept in a variant without the SUBGROUP capability.
pub fn check_capabilities(m: &Module, env: &Env, subgroup: bool, variant: &str) -> Result<()> {
    if subgroup {
        return Ok(());
    }
    let reach = reachable_functions(m, env, None);
    let mut first: Option<(Span, String)> = None;
    for (fi, keep) in reach.iter().enumerate() {
        if !keep {
            continue;
        }
        let f = &m.functions[fi];
        let subgroup_params: Vec<usize> = f
            .params
            .iter()
            .filter(|p| matches!(&p.io, Some(Io::Builtin(b)) if crate::ir::is_subgroup_builtin(b)))
            .map(|p| p.local)
            .collect();
        walk_block(&f.body, m, env, &mut |e| {
            if first.is_some() {
                return;
            }
            match &e.kind {
                ExprKind::Builtin(b, _) if b.subgroup => {
                    first = Some((e.span, format!("subgroup operation `{}`", b.wgsl)))
                }
                ExprKind::Local(l) if subgroup_params.contains(l) => {
                    first = Some((e.span, "subgroup builtin".into()))
                }
                _ => {}
            }
        });
    }
    match first {
        None => Ok(()),
        Some((span, what)) => Err(Error::new(
            span,
            format!(
                "{what} used in variant `{variant}`, which does not declare the subgroup capability; declare it with `requires(subgroup = <axis predicate>)` and guard this code with `if <axis> {{ .. }}`"
            ),
        )),
    }
}
