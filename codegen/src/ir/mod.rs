//! The typed intermediate representation of one DSL module.
//!
//! The front end builds it (every expression already carries its type and the Rust span that
//! produced it); the variant, printer, reflection and emit stages only read it. The IR holds
//! axis references unevaluated: a variant is the IR plus an axis environment
//! ([`crate::variants::Env`]). Nothing here knows about syn syntax trees or naga.

mod scalars;
mod tree;

pub use scalars::{Access, Scalar, StorageFormatTy, StructId, TexKind, TextureTy};
pub use tree::{ArrayLen, BinOp, Block, Builtin, Expr, ExprKind, Lit, Stmt, Ty, UnOp};

use proc_macro2::Span;

/// One DSL module (`#[shader] mod name { .. }`).
#[derive(Debug, Clone)]
pub struct Module {
    /// The `mod` name.
    pub name: String,
    /// Span of the `mod` name.
    pub span: Span,
    /// Declared variant axes, in declaration order.
    pub axes: Vec<Axis>,
    /// `exclude(..)` predicates over axes.
    pub excludes: Vec<Expr>,
    /// `requires(subgroup = ..)` predicate, if any.
    pub requires_subgroup: Option<Expr>,
    /// GPU structs.
    pub structs: Vec<Struct>,
    /// `const` items.
    pub consts: Vec<Const>,
    /// `static` items: resources and workgroup variables.
    pub globals: Vec<Global>,
    /// Functions, helpers and entry points, in declaration order.
    pub functions: Vec<Function>,
    /// A `#[library]` module: no entry points, and every function is kept (so that the
    /// library's own compilation validates all of its code).
    pub library: bool,
}

/// A typed compile-time parameter.
#[derive(Debug, Clone)]
pub struct Axis {
    /// Name used in expressions.
    pub name: String,
    /// Label used in variant names (defaults to `name`).
    pub label: String,
    /// `u32`, `i32` or `bool`.
    pub ty: Scalar,
    /// The values, in declaration order.
    pub values: Vec<Lit>,
    /// `unless value`: the value that adds nothing to variant names, so an axis added to a
    /// module keeps the names (and snapshots) of its variants at that value.
    pub unnamed: Option<Lit>,
    /// Span of the axis name.
    pub span: Span,
}

/// Where a struct is used, which decides its layout rules.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct StructUse {
    /// Reachable from a uniform buffer.
    pub uniform: bool,
    /// Reachable from a storage buffer.
    pub storage: bool,
    /// Used as entry point input or output.
    pub io: bool,
}

/// A struct declaration.
#[derive(Debug, Clone)]
pub struct Struct {
    /// Its name (both in WGSL and on the host).
    pub name: String,
    /// Fields in declaration order.
    pub fields: Vec<Field>,
    /// Span of the name.
    pub span: Span,
    /// How it is used (filled in after all items are lowered).
    pub uses: StructUse,
}

/// A struct field.
#[derive(Debug, Clone)]
pub struct Field {
    /// Field name.
    pub name: String,
    /// Field type.
    pub ty: Ty,
    /// `#[location]`/`#[builtin]` for entry point IO structs.
    pub io: Option<Io>,
    /// Span of the field name.
    pub span: Span,
}

/// Entry point input/output decoration.
#[derive(Debug, Clone, PartialEq)]
pub enum Io {
    /// `#[builtin(name)]`, the WGSL builtin name.
    Builtin(String),
    /// `#[builtin(position)] #[invariant]`: WGSL `@builtin(position) @invariant`.
    InvariantPosition,
    /// `#[location(n)]` with optional `#[interpolate(kind[, sampling])]`.
    Location {
        /// The location.
        location: u32,
        /// Interpolation type and sampling, WGSL spelling.
        interpolate: Option<(String, Option<String>)>,
    },
}

/// A `const` item.
#[derive(Debug, Clone)]
pub struct Const {
    /// Name.
    pub name: String,
    /// Declared type.
    pub ty: Ty,
    /// Value (a constant expression; may use axes).
    pub value: Expr,
    /// Span of the name.
    pub span: Span,
}

/// The address space (or resource class) of a `static`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Space {
    /// `#[uniform]`
    Uniform,
    /// `#[storage]`, `read_write` when writable.
    Storage {
        /// Declared `read_write`.
        read_write: bool,
    },
    /// Textures and samplers.
    Handle,
    /// `#[workgroup]`
    Workgroup,
}

/// A `static` item.
#[derive(Debug, Clone)]
pub struct Global {
    /// Name.
    pub name: String,
    /// Type.
    pub ty: Ty,
    /// Address space.
    pub space: Space,
    /// `(group, binding)` for resources.
    pub binding: Option<(u32, u32)>,
    /// For float textures: declared `unfilterable`.
    pub unfilterable: bool,
    /// `#[when(predicate)]`: the static exists only in variants where the predicate holds.
    pub when: Option<Expr>,
    /// Merged in from a library by `uses(..)`: a module with entry points leaves its binding
    /// out of variants that use nothing of its group ([`crate::variants::kept_globals`]).
    pub from_library: bool,
    /// Span of the name.
    pub span: Span,
}

/// Shader stage of an entry point.
#[derive(Debug, Clone)]
pub enum Stage {
    /// Compute, with its workgroup size expressions (may use axes).
    Compute(Box<[Expr; 3]>),
    /// Vertex.
    Vertex,
    /// Fragment.
    Fragment,
}

/// A local variable or parameter.
#[derive(Debug, Clone)]
pub struct Local {
    /// Unique (within the function) WGSL name.
    pub name: String,
    /// Type; `Ty::Ptr` for `&mut` parameters.
    pub ty: Ty,
    /// Declared `mut`.
    pub mutable: bool,
    /// Span of the binding.
    pub span: Span,
}

/// A function parameter.
#[derive(Debug, Clone)]
pub struct Param {
    /// The local it binds.
    pub local: usize,
    /// Entry point decoration.
    pub io: Option<Io>,
    /// For `mut` parameters, the name the WGSL parameter gets (the body copies it into a `var`).
    pub incoming: Option<String>,
}

/// A function: helper or entry point.
#[derive(Debug, Clone)]
pub struct Function {
    /// Name.
    pub name: String,
    /// `Some` for entry points.
    pub stage: Option<Stage>,
    /// `#[when(predicate)]` of an entry point: it exists only in variants where the predicate
    /// holds ([`crate::variants::entry_present`]).
    pub when: Option<Expr>,
    /// Parameters.
    pub params: Vec<Param>,
    /// Return type (`Ty::Unit` for none).
    pub ret: Ty,
    /// Decoration of a non-struct entry point result.
    pub ret_io: Option<Io>,
    /// All locals, parameters first.
    pub locals: Vec<Local>,
    /// Body.
    pub body: Block,
    /// Span of the name.
    pub span: Span,
}

impl Io {
    /// The WGSL builtin name, if this is a builtin.
    pub fn builtin(&self) -> Option<&str> {
        match self {
            Io::Builtin(b) => Some(b),
            Io::InvariantPosition => Some("position"),
            Io::Location { .. } => None,
        }
    }
}

/// Builtins that need the SUBGROUP capability.
pub fn is_subgroup_builtin(name: &str) -> bool {
    name.starts_with("subgroup_")
}

impl Module {
    /// Finds an axis by name.
    pub fn axis(&self, name: &str) -> Option<usize> {
        self.axes.iter().position(|a| a.name == name)
    }
}
