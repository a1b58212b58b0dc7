//! What one module's items name: the paths written in their code, the leaves of their `use`
//! trees and the names they define. Pure syntax, read with syn's visitor; resolving the paths to
//! the files that define them is `resolve`'s job.

use syn::punctuated::Punctuated;
use syn::visit::{self, Visit};

/// A path as written, by segment (`super::pool::plan_slots` is `["super", "pool", "plan_slots"]`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PathUse {
    pub segments: Vec<String>,
    pub line: usize,
    /// `use a::b::*`: names used in the module may resolve through it.
    pub glob: bool,
}

impl PathUse {
    pub fn text(&self) -> String {
        let text = self.segments.join("::");
        if self.glob {
            format!("{text}::*")
        } else {
            text
        }
    }
}

/// The item macro that re-exports like `pub use` (the renderer's internal items: `pub` with its
/// `internals` feature, `pub(crate)` without).
const REEXPORT_MACRO: &str = "internal_use";

/// One leaf of a `use` tree: the path it imports and the name it binds in the module.
#[derive(Debug, Clone)]
pub struct UseLeaf {
    pub path: PathUse,
    /// `None` for globs and `as _`.
    pub binding: Option<String>,
    /// `pub use` / `pub(crate) use`: a re-export, transparent to the file graph.
    pub reexport: bool,
}

/// Everything the non-module items of one module name and define.
#[derive(Debug, Default)]
pub struct Collected {
    /// Paths in code: types, expressions, patterns, trait bounds, macro paths and the
    /// expression arguments of macros.
    pub paths: Vec<PathUse>,
    /// `use` leaves, at module level or inside function bodies.
    pub uses: Vec<UseLeaf>,
    /// Names of items defined here (including items nested in function bodies).
    pub defs: Vec<String>,
}

/// Walks `items`, skipping `mod` items (the module tree handles those).
pub fn collect(items: &[syn::Item]) -> Collected {
    let mut c = Collected::default();
    for item in items {
        if !matches!(item, syn::Item::Mod(_)) {
            c.visit_item(item);
        }
    }
    c
}

fn line_of(ident: &syn::Ident) -> usize {
    ident.span().start().line
}

fn item_name(item: &syn::Item) -> Option<&syn::Ident> {
    match item {
        syn::Item::Const(i) => Some(&i.ident),
        syn::Item::Enum(i) => Some(&i.ident),
        syn::Item::Fn(i) => Some(&i.sig.ident),
        syn::Item::Macro(i) => i.ident.as_ref(),
        syn::Item::Static(i) => Some(&i.ident),
        syn::Item::Struct(i) => Some(&i.ident),
        syn::Item::Trait(i) => Some(&i.ident),
        syn::Item::TraitAlias(i) => Some(&i.ident),
        syn::Item::Type(i) => Some(&i.ident),
        syn::Item::Union(i) => Some(&i.ident),
        _ => None,
    }
}

fn flatten(
    tree: &syn::UseTree,
    prefix: &[String],
    line: usize,
    out: &mut Vec<(PathUse, Option<String>)>,
) {
    let with = |ident: &syn::Ident| {
        let mut p = prefix.to_vec();
        p.push(ident.to_string());
        p
    };
    let leaf = |segments: Vec<String>, line: usize, glob: bool| PathUse {
        segments,
        line,
        glob,
    };
    match tree {
        syn::UseTree::Path(p) => flatten(&p.tree, &with(&p.ident), line_of(&p.ident), out),
        syn::UseTree::Name(n) if n.ident == "self" => {
            out.push((leaf(prefix.to_vec(), line, false), prefix.last().cloned()));
        }
        syn::UseTree::Name(n) => {
            out.push((
                leaf(with(&n.ident), line_of(&n.ident), false),
                Some(n.ident.to_string()),
            ));
        }
        syn::UseTree::Rename(r) => {
            let segments = if r.ident == "self" {
                prefix.to_vec()
            } else {
                with(&r.ident)
            };
            let binding = (r.rename != "_").then(|| r.rename.to_string());
            out.push((leaf(segments, line_of(&r.ident), false), binding));
        }
        syn::UseTree::Glob(_) => out.push((leaf(prefix.to_vec(), line, true), None)),
        syn::UseTree::Group(g) => {
            for t in &g.items {
                flatten(t, prefix, line, out);
            }
        }
    }
}

impl<'ast> Visit<'ast> for Collected {
    fn visit_item(&mut self, item: &'ast syn::Item) {
        if let Some(name) = item_name(item) {
            self.defs.push(name.to_string());
        }
        visit::visit_item(self, item);
    }

    fn visit_item_mod(&mut self, _: &'ast syn::ItemMod) {
        // A module inside a function body: too rare to model; its own paths are skipped.
    }

    fn visit_item_use(&mut self, u: &'ast syn::ItemUse) {
        if u.leading_colon.is_some() {
            return; // `use ::other_crate::..`
        }
        let reexport = !matches!(u.vis, syn::Visibility::Inherited);
        let mut leaves = Vec::new();
        let line = u.use_token.span.start().line;
        flatten(&u.tree, &[], line, &mut leaves);
        self.uses
            .extend(leaves.into_iter().map(|(path, binding)| UseLeaf {
                path,
                binding,
                reexport,
            }));
    }

    fn visit_item_macro(&mut self, m: &'ast syn::ItemMacro) {
        // `macro_rules!` bodies are token patterns, not paths; other item macros are opaque.
        if m.ident.is_none() {
            // The renderer's `internal_use!(tree)`: a re-export, `pub` or `pub(crate)`.
            if m.mac.path.is_ident(REEXPORT_MACRO)
                && let Ok(tree) = m.mac.parse_body::<syn::UseTree>()
            {
                let mut leaves = Vec::new();
                let line = m.mac.bang_token.span.start().line;
                flatten(&tree, &[], line, &mut leaves);
                self.uses
                    .extend(leaves.into_iter().map(|(path, binding)| UseLeaf {
                        path,
                        binding,
                        reexport: true,
                    }));
                return;
            }
            self.visit_macro(&m.mac);
        }
    }

    fn visit_attribute(&mut self, _: &'ast syn::Attribute) {
        // `#[derive(..)]`, `#[cfg(..)]`, docs: never a path into this crate.
    }

    fn visit_visibility(&mut self, _: &'ast syn::Visibility) {
        // `pub(in crate::a)` names an ancestor module, not an item.
    }

    fn visit_expr_path(&mut self, e: &'ast syn::ExprPath) {
        if let Some(q) = e.qself.as_ref().filter(|q| q.position == 0) {
            // `<T>::f`: the path continues from a type, not from a module.
            return self.visit_type(&q.ty);
        }
        visit::visit_expr_path(self, e);
    }

    fn visit_type_path(&mut self, t: &'ast syn::TypePath) {
        if let Some(q) = t.qself.as_ref().filter(|q| q.position == 0) {
            return self.visit_type(&q.ty);
        }
        visit::visit_type_path(self, t);
    }

    fn visit_path(&mut self, path: &'ast syn::Path) {
        if path.leading_colon.is_none()
            && let Some(first) = path.segments.first()
        {
            self.paths.push(PathUse {
                segments: path.segments.iter().map(|s| s.ident.to_string()).collect(),
                line: line_of(&first.ident),
                glob: false,
            });
        }
        visit::visit_path(self, path); // generic arguments hold paths too
    }

    fn visit_macro(&mut self, mac: &'ast syn::Macro) {
        self.visit_path(&mac.path);
        // `assert_eq!(super::f(), x)`, `vec![crate::A]`, `format!(..)`: comma-separated
        // expressions are read; any other macro body stays opaque.
        let parser = Punctuated::<syn::Expr, syn::Token![,]>::parse_terminated;
        if let Ok(args) = mac.parse_body_with(parser) {
            for arg in &args {
                self.visit_expr(arg);
            }
        }
    }
}
