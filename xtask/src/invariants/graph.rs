//! The file graph of in-memory sources: one node per file module, one edge per path by which a
//! file uses an item *defined* in another file, and one to each other file whose import (a
//! re-export) the path goes through, even to another crate's item. `mod x;` and `pub use`
//! themselves are not edges; paths to other crates that no import of the crate carries are
//! ignored.

use super::modules::{FileId, Tree};
use super::resolve::{Edge, Resolver, Target};

#[derive(Debug)]
pub struct FileGraph {
    pub tree: Tree,
    /// In file and line order.
    pub edges: Vec<Edge>,
}

impl FileGraph {
    /// Parses every file the crate roots among `sources` reach and resolves their paths.
    pub fn new(sources: &[(String, String)]) -> Result<Self, String> {
        let tree = Tree::build(sources)?;
        let edges = Resolver::new(&tree).edges();
        Ok(Self { tree, edges })
    }

    pub fn file(&self, id: FileId) -> &str {
        &self.tree.files[id]
    }

    /// Per file under `from`, every path in it that names an item defined under `to`, or that
    /// goes through a module under `to` (a re-export there counts), as `line N: path`.
    pub fn uses_into(&self, from: &str, to: &str) -> Vec<(String, Vec<String>)> {
        let resolver = Resolver::new(&self.tree);
        let under = |dir: &str, f: FileId| self.file(f).starts_with(dir);
        let mut found: Vec<(FileId, usize, String)> = Vec::new();
        for (m, module) in self.tree.modules.iter().enumerate() {
            if !under(from, module.file) || under(to, module.file) {
                continue;
            }
            for path in &module.uses {
                let defined_under = match resolver.resolve(m, &path.segments) {
                    Some(Target::Item(f)) => under(to, f),
                    _ => false,
                };
                if defined_under
                    || resolver
                        .files_on_the_way(m, path)
                        .into_iter()
                        .any(|f| under(to, f))
                {
                    found.push((module.file, path.line, path.text()));
                }
            }
        }
        found.sort();
        found.dedup();
        let mut per_file: Vec<(String, Vec<String>)> = Vec::new();
        for (f, line, path) in found {
            let use_ = format!("line {line}: {path}");
            match per_file.last_mut() {
                Some((file, uses)) if file == self.file(f) => uses.push(use_),
                _ => per_file.push((self.file(f).to_owned(), vec![use_])),
            }
        }
        per_file
    }
}
