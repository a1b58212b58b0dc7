//! Resolving a path written in a module to what it names: a module, or the file that *defines*
//! the item. `crate::`, `super::` and `self::` walk the module tree; other first segments are
//! looked up among the module's own names (items, child modules, imports, then globs), and
//! imports are followed to their source, so re-exports are transparent. Anything not found
//! (other crates, the prelude, local variables, generics) resolves to nothing.

use std::collections::HashSet;

use super::modules::{Binding, FileId, ModId, Tree};
use super::uses::PathUse;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    Module(ModId),
    Item(FileId),
}

/// "File `from` uses an item defined in file `to`", with the path that shows it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Edge {
    pub from: FileId,
    pub to: FileId,
    pub line: usize,
    pub path: String,
}

/// Imports and globs being followed, so a re-export loop (`pub use a::*` in `b`, and back)
/// ends instead of recursing forever.
type Visiting = HashSet<(ModId, String, usize)>;

pub struct Resolver<'t> {
    tree: &'t Tree,
}

impl<'t> Resolver<'t> {
    pub fn new(tree: &'t Tree) -> Self {
        Self { tree }
    }

    /// What `segments`, written in module `from`, names.
    pub fn resolve(&self, from: ModId, segments: &[String]) -> Option<Target> {
        self.resolve_in(from, segments, &mut Visiting::new())
    }

    fn resolve_in(&self, from: ModId, segments: &[String], seen: &mut Visiting) -> Option<Target> {
        let modules = &self.tree.modules;
        let (first, rest) = segments.split_first()?;
        let mut current = match first.as_str() {
            "crate" => Target::Module(modules[from].root),
            "self" => Target::Module(from),
            "super" => Target::Module(modules[from].parent?),
            "Self" => return None,
            name => self.lookup(from, name, rest.is_empty(), seen)?,
        };
        for (i, segment) in rest.iter().enumerate() {
            let Target::Module(m) = current else {
                break; // an item's variant or associated item: the item's file defines it
            };
            current = match segment.as_str() {
                "super" => Target::Module(modules[m].parent?),
                "self" => current,
                name => self.lookup(m, name, i + 1 == rest.len(), seen)?,
            };
        }
        Some(current)
    }

    /// `name` in module `m`: its own bindings first (a module when more segments follow, an item
    /// at the end of the path, the other kind otherwise), then its globs.
    fn lookup(&self, m: ModId, name: &str, last: bool, seen: &mut Visiting) -> Option<Target> {
        let module = &self.tree.modules[m];
        let wanted = |t: &Target| matches!(t, Target::Module(_)) != last;
        let mut fallback = None;
        let bindings = module
            .names
            .get(name)
            .map(Vec::as_slice)
            .unwrap_or_default();
        // Direct bindings before imports: `mod a; pub use a::a;` must find module `a` while
        // resolving the import of `a::a`.
        for binding in bindings {
            let target = match binding {
                Binding::Module(child) => Target::Module(*child),
                Binding::Item(file) => Target::Item(*file),
                Binding::Import(_) => continue,
            };
            if wanted(&target) {
                return Some(target);
            }
            fallback = fallback.or(Some(target));
        }
        for (i, binding) in bindings.iter().enumerate() {
            let Binding::Import(path) = binding else {
                continue;
            };
            if !seen.insert((m, name.to_owned(), i)) {
                continue;
            }
            let target = self.resolve_in(m, &path.segments, seen);
            seen.remove(&(m, name.to_owned(), i));
            match target {
                Some(t) if wanted(&t) => return Some(t),
                Some(t) => fallback = fallback.or(Some(t)),
                None => {}
            }
        }
        if fallback.is_some() {
            return fallback;
        }
        for (i, glob) in module.globs.iter().enumerate() {
            // Globs are keyed apart from named imports by an index past them.
            let key = (m, name.to_owned(), usize::MAX - i);
            if !seen.insert(key.clone()) {
                continue;
            }
            let found = match self.resolve_in(m, &glob.segments, seen) {
                Some(Target::Module(g)) => self.lookup(g, name, last, seen),
                _ => None, // a glob over an enum's variants: its `use` is the edge
            };
            seen.remove(&key);
            if found.is_some() {
                return found;
            }
        }
        None
    }

    /// Every edge of the tree: each path a module uses that resolves to an item of another file,
    /// in file and line order (a file's repeated uses of one path are all listed).
    pub fn edges(&self) -> Vec<Edge> {
        let mut edges: Vec<Edge> = (0..self.tree.modules.len())
            .flat_map(|m| {
                let from = self.tree.modules[m].file;
                self.tree.modules[m].uses.iter().filter_map(move |path| {
                    match self.resolve(m, &path.segments)? {
                        Target::Item(to) if to != from => Some(Edge {
                            from,
                            to,
                            line: path.line,
                            path: path.text(),
                        }),
                        _ => None,
                    }
                })
            })
            .collect();
        edges.sort_by(|a, b| (a.from, a.line, a.to, &a.path).cmp(&(b.from, b.line, b.to, &b.path)));
        edges.dedup();
        edges
    }

    /// The files of the modules that `path`, written in module `m`, passes through on its way
    /// (`crate::frame::Renderer` passes through `frame/mod.rs` even if `Renderer` is defined
    /// elsewhere and re-exported there).
    pub fn files_on_the_way(&self, m: ModId, path: &PathUse) -> Vec<FileId> {
        (1..path.segments.len())
            .filter_map(|n| match self.resolve(m, &path.segments[..n]) {
                Some(Target::Module(via)) => Some(self.tree.modules[via].file),
                _ => None,
            })
            .collect()
    }
}
