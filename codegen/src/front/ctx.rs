//! Lowering state: the module context (every module-level name, with where it came from) and
//! the function context (locals, scopes, unique WGSL names). Every lowering file builds on these;
//! this file imports none of them.

use crate::ir::{self, Expr, ExprKind, Local, Module, Ty};
use proc_macro2::Span;
use std::collections::HashMap;
use syn::{Error, Result};

/// What is being lowered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// A `#[shader]` module, all of it.
    Shader,
    /// Only the declarations the host side sees (axes, structs, consts, statics), skipping
    /// functions and whole-module checks. Used to emit a useful stub next to an error.
    Declarations,
    /// A `#[library]` module: no entry points, every function kept.
    Library,
}

/// Module-level lowering state.
pub(crate) struct ModCtx {
    pub module: Module,
    pub struct_ids: HashMap<String, usize>,
    pub const_ids: HashMap<String, usize>,
    pub global_ids: HashMap<String, usize>,
    pub fn_ids: HashMap<String, usize>,
    /// Calls made by each function: `(callee, span)`.
    pub calls: Vec<Vec<(usize, Span)>>,
    /// Every module-level name, for conflict checks.
    pub names: HashMap<String, Span>,
    /// The library each module-level name came from, as errors name it (`None`: the module
    /// itself).
    pub origins: HashMap<String, Option<String>>,
    /// The library of the items being lowered now (`None`: the module itself).
    pub origin: Option<String>,
}

impl ModCtx {
    /// An empty context for the module `item`.
    pub(crate) fn new(item: &syn::ItemMod) -> Self {
        ModCtx {
            module: Module {
                name: item.ident.to_string(),
                span: item.ident.span(),
                axes: vec![],
                excludes: vec![],
                requires_subgroup: None,
                structs: vec![],
                consts: vec![],
                globals: vec![],
                functions: vec![],
                library: false,
            },
            struct_ids: HashMap::new(),
            const_ids: HashMap::new(),
            global_ids: HashMap::new(),
            fn_ids: HashMap::new(),
            calls: vec![],
            names: HashMap::new(),
            origins: HashMap::new(),
            origin: None,
        }
    }
}

/// Function-level lowering state (also used, with `const_only`, for constant expressions).
pub(crate) struct FnCtx<'a> {
    pub m: &'a ModCtx,
    pub locals: Vec<Local>,
    scopes: Vec<HashMap<String, usize>>,
    used_names: HashMap<String, u32>,
    pub ret: Ty,
    pub calls: Vec<(usize, Span)>,
    pub const_only: bool,
    pub loop_depth: u32,
    /// Lowering the body of a vertex or compute entry point, where `discard()` is an error.
    pub non_fragment_entry: bool,
}

/// Whether WGSL reserves this identifier, or predeclares it (builtin functions and types).
pub(crate) fn wgsl_reserved(name: &str) -> bool {
    naga::keywords::wgsl::RESERVED_SET.contains(name)
        || naga::keywords::wgsl::BUILTIN_IDENTIFIER_SET.contains(name)
        || name.starts_with("__")
}

impl<'a> FnCtx<'a> {
    pub(crate) fn new(m: &'a ModCtx, const_only: bool) -> Self {
        FnCtx {
            m,
            locals: vec![],
            scopes: vec![HashMap::new()],
            used_names: HashMap::new(),
            ret: Ty::Unit,
            calls: vec![],
            const_only,
            loop_depth: 0,
            non_fragment_entry: false,
        }
    }

    /// A context for a function body whose parameters are already lowered.
    pub(crate) fn for_function(m: &'a ModCtx, f: &ir::Function, rust_names: &[String]) -> Self {
        let mut cx = FnCtx::new(m, false);
        cx.ret = f.ret.clone();
        cx.non_fragment_entry = matches!(f.stage, Some(ir::Stage::Vertex | ir::Stage::Compute(_)));
        for (i, l) in f.locals.iter().enumerate() {
            cx.used_names.insert(l.name.clone(), 0);
            cx.scopes[0].insert(rust_names[i].clone(), i);
            cx.locals.push(l.clone());
        }
        for p in &f.params {
            if let Some(n) = &p.incoming {
                cx.used_names.insert(n.clone(), 0);
            }
        }
        cx
    }

    /// Declares a local in the innermost scope, giving it a unique WGSL name.
    pub(crate) fn declare(&mut self, rust_name: &str, ty: Ty, mutable: bool, span: Span) -> usize {
        let name = self.fresh_name(rust_name);
        let id = self.locals.len();
        self.locals.push(Local {
            name,
            ty,
            mutable,
            span,
        });
        #[expect(
            clippy::expect_used,
            reason = "a function body opens its scope before any local is declared"
        )]
        self.scopes
            .last_mut()
            .expect("a scope is open")
            .insert(rust_name.to_string(), id);
        id
    }

    /// The name the source uses for local `l`, where a scope in reach binds it.
    pub(crate) fn source_name(&self, l: usize) -> Option<&str> {
        self.scopes
            .iter()
            .rev()
            .find_map(|s| s.iter().find(|(_, id)| **id == l).map(|(n, _)| n.as_str()))
    }

    /// A local the source never names (a `for` loop's hoisted end): in no scope.
    pub(crate) fn hidden_local(&mut self, name: &str, ty: Ty, span: Span) -> usize {
        let name = self.fresh_name(name);
        self.locals.push(Local {
            name,
            ty,
            mutable: false,
            span,
        });
        self.locals.len() - 1
    }

    /// Whether `e` has the same value wherever it is evaluated in the function: it reads no
    /// mutable local, no writable static (a buffer or workgroup variable the body may write)
    /// and calls no function.
    pub(crate) fn loop_invariant(&self, e: &Expr) -> bool {
        let children: Vec<&Expr> = match &e.kind {
            ExprKind::Lit(_) | ExprKind::Const(_) | ExprKind::Axis(_) => return true,
            ExprKind::Local(l) => return !self.locals[*l].mutable,
            // Uniforms and read-only buffers cannot change during the dispatch; writable buffers
            // and workgroup memory can.
            ExprKind::Global(g) => {
                return matches!(
                    self.m.module.globals[*g].space,
                    ir::Space::Uniform
                        | ir::Space::Storage { read_write: false }
                        | ir::Space::Handle
                );
            }
            ExprKind::Call(..) | ExprKind::Deref(_) => return false,
            // `arr.len()` of a runtime-sized buffer is fixed for the dispatch.
            ExprKind::Builtin(b, _) if b.wgsl == "arrayLength" => return true,
            ExprKind::Builtin(b, _) if b.pointer_first => return false,
            ExprKind::Unary(_, a)
            | ExprKind::Cast(a)
            | ExprKind::Field(a, _)
            | ExprKind::Swizzle(a, _)
            | ExprKind::AddrOf(a) => vec![a],
            ExprKind::Binary(_, a, b) | ExprKind::Index(a, b) => vec![a, b],
            ExprKind::Construct(args) | ExprKind::Builtin(_, args) => args.iter().collect(),
        };
        children.into_iter().all(|c| self.loop_invariant(c))
    }

    pub(crate) fn fresh_name(&mut self, rust_name: &str) -> String {
        let mut base = rust_name.trim_start_matches('_').to_string();
        if base.is_empty() {
            base = "v".into();
        }
        if wgsl_reserved(&base) || self.m.names.contains_key(&base) {
            base.push('_');
        }
        let mut name = base.clone();
        let mut n = 0;
        while self.used_names.contains_key(&name) {
            n += 1;
            name = format!("{base}_{n}");
        }
        self.used_names.insert(name.clone(), 0);
        name
    }

    pub(crate) fn lookup_local(&self, name: &str) -> Option<usize> {
        self.scopes.iter().rev().find_map(|s| s.get(name).copied())
    }

    pub(crate) fn push_scope(&mut self) {
        self.scopes.push(HashMap::new());
    }

    pub(crate) fn pop_scope(&mut self) {
        self.scopes.pop();
    }

    /// Lowers a constant expression (literals, consts, axes and operators).
    pub(crate) fn const_expr(&mut self, e: &syn::Expr) -> Result<Expr> {
        let saved = std::mem::replace(&mut self.const_only, true);
        let r = self.expr(e);
        self.const_only = saved;
        r
    }
}

pub(crate) fn register(m: &mut ModCtx, name: &syn::Ident, what: &str) -> Result<()> {
    let s = name.to_string();
    if wgsl_reserved(&s) {
        return Err(Error::new(
            name.span(),
            format!("`{s}` is a reserved word or builtin name in WGSL; rename this {what}"),
        ));
    }
    if let Some(first) = m.names.insert(s.clone(), name.span()) {
        let before = m.origins.get(&s).cloned().flatten();
        let msg = match (&before, &m.origin) {
            (None, None) => format!(
                "the name `{s}` is defined twice in this shader module (types, values and axes share one namespace)"
            ),
            (Some(lib), None) | (None, Some(lib)) => format!(
                "the name `{s}` is defined both in {lib} and in this module (a module and the libraries it uses share one namespace); rename one of them"
            ),
            (Some(a), Some(b)) => format!(
                "the name `{s}` is defined in both {a} and {b} (the libraries a module uses, and the libraries they use, share one namespace)"
            ),
        };
        let mut err = Error::new(name.span(), msg);
        if before.is_some() || m.origin.is_some() {
            err.combine(Error::new(first, format!("`{s}` is first defined here")));
        }
        return Err(err);
    }
    m.origins.insert(s, m.origin.clone());
    Ok(())
}
