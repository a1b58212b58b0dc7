//! The library graph: a module's `uses(..)`, the libraries those use, and so on, ordered so
//! that every library comes after the libraries it uses and appears once (a diamond merges
//! its shared library once). A cycle is an error at the `uses(..)` path that closes it, naming
//! the route around it.
//!
//! How a path finds its library is the caller's business (the proc-macro chain compares full
//! paths, the source-text tools the last segment), so the ordering takes a resolver.

use super::libs::{Library, path_text, route_text};
use syn::spanned::Spanned;
use syn::{Error, Result};

/// The module or library being compiled, as the graph sees it.
pub(crate) struct Root<'a> {
    /// Its module name, for messages.
    pub name: String,
    /// Its own `uses(..)`, in order.
    pub uses: &'a [syn::Path],
    /// For a library being compiled: its `mod` item, so that a library reached through the
    /// graph that is this very library is recognised as a cycle.
    pub library_item: Option<&'a syn::ItemMod>,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Mark {
    New,
    Open,
    Done,
}

struct Walk<'a> {
    libs: &'a [Library],
    resolve: &'a dyn Fn(&syn::Path) -> Result<usize>,
    root_name: String,
    /// The library in `libs` that is the root itself (a library compiled with its graph).
    root_index: Option<usize>,
    marks: Vec<Mark>,
    routes: Vec<Vec<syn::Path>>,
    direct: Vec<Vec<usize>>,
    order: Vec<usize>,
}

impl Walk<'_> {
    fn edge(&mut self, path: &syn::Path, from: &[syn::Path]) -> Result<usize> {
        let mut route = from.to_vec();
        route.push(path.clone());
        let j = (self.resolve)(path)?;
        if Some(j) == self.root_index {
            return Err(Error::new(
                path.span(),
                format!(
                    "library cycle: `{}` uses itself through {}; a library graph must have no cycles",
                    self.root_name,
                    route_text(&route)
                ),
            ));
        }
        match self.marks[j] {
            Mark::Done => return Ok(j),
            Mark::Open => {
                let start = self.routes[j].len() - 1;
                return Err(Error::new(
                    path.span(),
                    format!(
                        "library cycle: {}; a library graph must have no cycles",
                        route_text(&route[start..])
                    ),
                ));
            }
            Mark::New => {}
        }
        self.marks[j] = Mark::Open;
        self.routes[j] = route.clone();
        for dep in self.libs[j].uses_paths()? {
            let k = self.edge(&dep, &route)?;
            if !self.direct[j].contains(&k) {
                self.direct[j].push(k);
            }
        }
        self.marks[j] = Mark::Done;
        self.order.push(j);
        Ok(j)
    }
}

fn same_item(a: &syn::ItemMod, b: &syn::ItemMod) -> bool {
    a.ident == b.ident
        && quote::ToTokens::to_token_stream(a).to_string()
            == quote::ToTokens::to_token_stream(b).to_string()
}

/// Orders `libs` (every library the root reaches, in any order; `resolve` maps a `uses(..)`
/// path to its index in `libs`) for merging: dependencies first, each library once, with its
/// route and direct uses set. Libraries the root does not reach are dropped.
pub(crate) fn order(
    root: &Root,
    libs: &[Library],
    resolve: &dyn Fn(&syn::Path) -> Result<usize>,
) -> Result<Vec<Library>> {
    let n = libs.len();
    let mut walk = Walk {
        libs,
        resolve,
        root_name: root.name.clone(),
        root_index: root
            .library_item
            .and_then(|item| libs.iter().position(|l| same_item(&l.item, item))),
        marks: vec![Mark::New; n],
        routes: vec![vec![]; n],
        direct: vec![vec![]; n],
        order: vec![],
    };
    for p in root.uses {
        walk.edge(p, &[])?;
    }
    let mut position = vec![usize::MAX; n];
    for (at, &i) in walk.order.iter().enumerate() {
        position[i] = at;
    }
    Ok(walk
        .order
        .iter()
        .map(|&i| {
            let mut lib = libs[i].clone();
            lib.path = walk.routes[i].last().cloned().unwrap_or(lib.path);
            lib.route = walk.routes[i].clone();
            lib.uses = walk.direct[i].iter().map(|&k| position[k]).collect();
            lib
        })
        .collect())
}

/// The indices of the libraries `libs[i]` reaches (itself excluded), in the list's order:
/// what `libs[i]` is compiled with on its own.
pub(crate) fn reached_by(libs: &[Library], i: usize) -> Vec<usize> {
    let mut reached = vec![false; libs.len()];
    let mut stack = libs[i].uses.clone();
    while let Some(k) = stack.pop() {
        if !std::mem::replace(&mut reached[k], true) {
            stack.extend(libs[k].uses.iter().copied());
        }
    }
    (0..libs.len()).filter(|&k| reached[k]).collect()
}

/// A resolver by full path (as written, spaces ignored) among libraries collected by path. A
/// library reached by two paths (`other_crate::lib` from a module, `$crate::lib` from a library
/// of that crate) resolves to one node: the first collected with the same item.
pub(crate) fn by_full_path(libs: &[Library]) -> impl Fn(&syn::Path) -> Result<usize> + '_ {
    move |p: &syn::Path| {
        let want = path_text(p);
        libs.iter()
            .position(|l| path_text(&l.path) == want)
            .map(|i| {
                libs.iter()
                    .position(|l| same_item(&l.item, &libs[i].item))
                    .unwrap_or(i)
            })
            .ok_or_else(|| {
                Error::new(
                    p.span(),
                    format!("no library was found at `{want}` for this `uses(..)` path"),
                )
            })
    }
}
