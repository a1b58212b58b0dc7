//! The module trees of crates given as in-memory sources: each crate root (`src/lib.rs`,
//! `src/main.rs`, `src/bin/*.rs`) and every `mod x;` it reaches (`x.rs` or `x/mod.rs`), inline
//! `mod x { .. }` blocks as modules of their file, and per module the names it binds (items,
//! child modules, imports, globs) and the paths it uses.

use std::collections::HashMap;

use super::uses::{self, PathUse};

pub type FileId = usize;
pub type ModId = usize;

/// What a name in a module stands for.
#[derive(Debug, Clone)]
pub enum Binding {
    Module(ModId),
    /// An item (fn, type, const, macro..) defined in this module's file.
    Item(FileId),
    /// `use path;`, resolved from this module when looked up.
    Import(PathUse),
}

#[derive(Debug, Default)]
pub struct Module {
    pub parent: Option<ModId>,
    pub root: ModId,
    pub file: FileId,
    pub names: HashMap<String, Vec<Binding>>,
    /// Targets of `use a::*` (re-exporting or not).
    pub globs: Vec<PathUse>,
    /// Paths whose targets are this module's dependencies: code paths and non-`pub` `use` leaves.
    pub uses: Vec<PathUse>,
}

/// Every module of the crates found in the sources.
#[derive(Debug, Default)]
pub struct Tree {
    pub files: Vec<String>,
    pub modules: Vec<Module>,
}

/// Is `path` a crate root, and if so the directory its `mod` declarations start from?
fn crate_root_dir(path: &str) -> Option<&str> {
    let (dir, name) = path.rsplit_once('/').unwrap_or(("", path));
    let is_root = match dir.rsplit_once('/').map_or(dir, |(_, last)| last) {
        "src" => name == "lib.rs" || name == "main.rs",
        "bin" => dir.ends_with("src/bin") && name.ends_with(".rs"),
        _ => false,
    };
    is_root.then(|| &path[..path.len() - name.len()])
}

impl Tree {
    /// Builds the trees of every crate root in `sources` (path, text). Files no root reaches are
    /// ignored. Fails on a file syn cannot parse.
    pub fn build(sources: &[(String, String)]) -> Result<Self, String> {
        let by_path: HashMap<&str, &str> = sources
            .iter()
            .map(|(p, t)| (p.as_str(), t.as_str()))
            .collect();
        let mut tree = Tree::default();
        let mut roots: Vec<(&str, &str)> = sources
            .iter()
            .filter_map(|(p, _)| crate_root_dir(p).map(|d| (p.as_str(), d)))
            .collect();
        roots.sort_unstable();
        for (path, dir) in roots {
            let id = tree.modules.len();
            tree.add_file_module(&by_path, path, None, id, dir.to_owned())?;
        }
        Ok(tree)
    }

    fn add_file_module(
        &mut self,
        by_path: &HashMap<&str, &str>,
        path: &str,
        parent: Option<ModId>,
        root: ModId,
        dir: String,
    ) -> Result<ModId, String> {
        let text = by_path[path];
        let file = syn::parse_file(text).map_err(|e| {
            let at = e.span().start();
            format!("{path}:{}:{}: {e}", at.line, at.column + 1)
        })?;
        let file_id = self.files.len();
        self.files.push(path.to_owned());
        self.add_module(by_path, &file.items, file_id, parent, root, dir)
    }

    fn add_module(
        &mut self,
        by_path: &HashMap<&str, &str>,
        items: &[syn::Item],
        file: FileId,
        parent: Option<ModId>,
        root: ModId,
        dir: String,
    ) -> Result<ModId, String> {
        let id = self.modules.len();
        self.modules.push(Module {
            parent,
            root,
            file,
            ..Module::default()
        });
        let collected = uses::collect(items);
        let m = &mut self.modules[id];
        for name in collected.defs {
            m.names.entry(name).or_default().push(Binding::Item(file));
        }
        for leaf in collected.uses {
            if let Some(name) = leaf.binding {
                let binding = Binding::Import(leaf.path.clone());
                m.names.entry(name).or_default().push(binding);
            }
            if leaf.path.glob {
                m.globs.push(leaf.path.clone());
            }
            if !leaf.reexport {
                m.uses.push(leaf.path);
            }
        }
        m.uses.extend(collected.paths);
        for item in items {
            let syn::Item::Mod(child) = item else {
                continue;
            };
            let name = child.ident.to_string();
            let child_dir = format!("{dir}{name}/");
            let child_id = match &child.content {
                Some((_, inner)) => {
                    Some(self.add_module(by_path, inner, file, Some(id), root, child_dir)?)
                }
                None => match [format!("{dir}{name}.rs"), format!("{dir}{name}/mod.rs")]
                    .into_iter()
                    .find(|p| by_path.contains_key(p.as_str()))
                {
                    Some(p) => {
                        Some(self.add_file_module(by_path, &p, Some(id), root, child_dir)?)
                    }
                    None => None,
                },
            };
            // A module without a file among the sources (generated, or outside) binds nothing.
            if let Some(child_id) = child_id {
                let binding = Binding::Module(child_id);
                self.modules[id]
                    .names
                    .entry(name)
                    .or_default()
                    .push(binding);
            }
        }
        Ok(id)
    }
}
