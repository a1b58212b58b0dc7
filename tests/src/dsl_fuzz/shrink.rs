//! The candidates a failing expression shrinks to: each subtree replaced by a same-typed
//! descendant or by an input leaf.

use super::ast::{E, Kind, T};

fn e(ty: T, kind: Kind) -> E {
    E { ty, kind }
}

fn b(x: E) -> Box<E> {
    Box::new(x)
}

/// Smaller expressions of the same type: each subtree replaced by a same-typed descendant or
/// by an input leaf, smallest first.
pub fn shrink_candidates(x: &E) -> Vec<E> {
    let mut out = vec![];
    let n = x.size();
    for path in 0..n {
        for replacement in replacements(node_at(x, path)) {
            let mut y = x.clone();
            *node_at_mut(&mut y, path) = replacement;
            if y.has_input() && y.size() < n {
                out.push(y);
            }
        }
    }
    out.sort_by_key(E::size);
    out.dedup();
    out
}

fn replacements(x: &E) -> Vec<E> {
    let mut out = vec![];
    if !matches!(x.kind, Kind::Input(0)) {
        let leaf = e(T::scalar(x.ty.s), Kind::Input(0));
        out.push(if x.ty.n == 1 {
            leaf
        } else {
            e(x.ty, Kind::Splat(b(leaf)))
        });
    }
    fn descendants<'a>(x: &'a E, ty: T, out: &mut Vec<&'a E>) {
        for c in x.children() {
            if c.ty == ty {
                out.push(c);
            }
            descendants(c, ty, out);
        }
    }
    let mut d = vec![];
    descendants(x, x.ty, &mut d);
    out.extend(d.into_iter().cloned());
    out
}

/// The node at pre-order position `i`.
fn node_at(x: &E, i: usize) -> &E {
    fn go<'a>(x: &'a E, i: &mut usize) -> Option<&'a E> {
        if *i == 0 {
            return Some(x);
        }
        *i -= 1;
        x.children().into_iter().find_map(|c| go(c, i))
    }
    go(x, &mut { i }).expect("position within the tree")
}

fn node_at_mut(x: &mut E, i: usize) -> &mut E {
    fn go<'a>(x: &'a mut E, i: &mut usize) -> Option<&'a mut E> {
        if *i == 0 {
            return Some(x);
        }
        *i -= 1;
        for c in x.children_mut() {
            if let Some(found) = go(c, i) {
                return Some(found);
            }
        }
        None
    }
    go(x, &mut { i }).expect("position within the tree")
}
