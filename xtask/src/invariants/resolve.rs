//! Resolving a path written in a module to what it names: a module, or the file that *defines*
//! the item. `crate::`, `super::` and `self::` walk the module tree; other first segments are
//! looked up among the module's own names (items, child modules, imports, then globs), and
//! imports are followed to their source. Anything not found (other crates, the prelude, local
//! variables, generics) resolves to nothing.
//!
//! A path that reaches its item through an import of another file (a re-export: `pub use` in
//! `b.rs`, used as `b::X` from `a.rs`) depends on that file as well as on the file that defines
//! the item: the edges go to both. Only to the origin, `a.rs` could take a name from `b.rs` while
//! `b.rs` uses `a.rs`, a circle no edge would show; only to `b.rs`, a circle between `a.rs` and
//! the defining file would hide behind it. A re-export of another crate's item still ties the
//! user to the re-exporting file.

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
        self.resolve_in(from, segments, &mut Visiting::new(), &mut vec![])
    }

    /// What `segments`, written in module `from`, names, and the files whose imports the path
    /// goes through on the way (the re-exports it relies on; also when the item is in another
    /// crate and the path resolves to nothing here).
    pub fn resolve_traced(
        &self,
        from: ModId,
        segments: &[String],
    ) -> (Option<Target>, Vec<FileId>) {
        let mut via = vec![];
        let target = self.resolve_in(from, segments, &mut Visiting::new(), &mut via);
        via.sort_unstable();
        via.dedup();
        (target, via)
    }

    /// [`Resolver::resolve`], adding to `via` the file of each import followed.
    fn resolve_in(
        &self,
        from: ModId,
        segments: &[String],
        seen: &mut Visiting,
        via: &mut Vec<FileId>,
    ) -> Option<Target> {
        let modules = &self.tree.modules;
        let (first, rest) = segments.split_first()?;
        let mut current = match first.as_str() {
            "crate" => Target::Module(modules[from].root),
            "self" => Target::Module(from),
            "super" => Target::Module(modules[from].parent?),
            "Self" => return None,
            name => self.lookup(from, name, rest.is_empty(), seen, via)?,
        };
        for (i, segment) in rest.iter().enumerate() {
            let Target::Module(m) = current else {
                break; // an item's variant or associated item: the item's file defines it
            };
            current = match segment.as_str() {
                "super" => Target::Module(modules[m].parent?),
                "self" => current,
                name => self.lookup(m, name, i + 1 == rest.len(), seen, via)?,
            };
        }
        Some(current)
    }

    /// `name` in module `m`: its own bindings first (a module when more segments follow, an item
    /// at the end of the path, the other kind otherwise), then its globs. A name found through an
    /// import or glob of `m` adds `m`'s file to `via`, with the files its path goes through.
    fn lookup(
        &self,
        m: ModId,
        name: &str,
        last: bool,
        seen: &mut Visiting,
        via: &mut Vec<FileId>,
    ) -> Option<Target> {
        let module = &self.tree.modules[m];
        let wanted = |t: &Target| matches!(t, Target::Module(_)) != last;
        let mut fallback = None;
        // The files the fallback, when it came through an import, went through.
        let mut fallback_via: Option<Vec<FileId>> = None;
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
        // An import naming something outside the crate: the name still comes from this file.
        let mut imported_from_outside = false;
        for (i, binding) in bindings.iter().enumerate() {
            let Binding::Import(path) = binding else {
                continue;
            };
            if !seen.insert((m, name.to_owned(), i)) {
                continue;
            }
            let mark = via.len();
            let target = self.resolve_in(m, &path.segments, seen, via);
            seen.remove(&(m, name.to_owned(), i));
            match target {
                Some(t) if wanted(&t) => {
                    via.push(module.file);
                    return Some(t);
                }
                Some(t) if fallback.is_none() => {
                    fallback = Some(t);
                    fallback_via = Some(via.split_off(mark));
                }
                Some(_) => via.truncate(mark),
                None => imported_from_outside = true,
            }
        }
        if fallback.is_some() {
            if let Some(through) = fallback_via {
                via.extend(through);
                via.push(module.file);
            }
            return fallback;
        }
        if imported_from_outside {
            via.push(module.file);
        }
        for (i, glob) in module.globs.iter().enumerate() {
            // Globs are keyed apart from named imports by an index past them.
            let key = (m, name.to_owned(), usize::MAX - i);
            if !seen.insert(key.clone()) {
                continue;
            }
            let mark = via.len();
            let found = match self.resolve_in(m, &glob.segments, seen, via) {
                Some(Target::Module(g)) => self.lookup(g, name, last, seen, via),
                _ => None, // a glob over an enum's variants: its `use` is the edge
            };
            seen.remove(&key);
            if found.is_some() {
                via.push(module.file);
                return found;
            }
            via.truncate(mark);
        }
        None
    }

    /// Every edge of the tree: each path a module uses that resolves to an item of another file,
    /// or goes through an import (a re-export) in another file, to each of those files; in file
    /// and line order (a file's repeated uses of one path are all listed).
    pub fn edges(&self) -> Vec<Edge> {
        let mut edges: Vec<Edge> = (0..self.tree.modules.len())
            .flat_map(|m| {
                let from = self.tree.modules[m].file;
                self.tree.modules[m].uses.iter().flat_map(move |path| {
                    let (target, mut to) = self.resolve_traced(m, &path.segments);
                    if let Some(Target::Item(defined)) = target {
                        to.push(defined);
                    }
                    to.into_iter()
                        .filter(move |&to| to != from)
                        .map(move |to| Edge {
                            from,
                            to,
                            line: path.line,
                            path: path.text(),
                        })
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
