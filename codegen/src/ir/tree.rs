//! The recursive part of the IR: types (whose array lengths are unevaluated expressions that may
//! use axes, so two array types compare equal whatever their lengths: naga checks lengths per
//! variant), and typed expressions and statements, each carrying its type and source span.
//! Types and expressions refer to each other, so they live in one file.

use super::scalars::{Access, Scalar, StorageFormatTy, StructId, TextureTy};
use proc_macro2::Span;

/// A literal value (also the value of an axis).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Lit {
    /// `true` / `false`
    Bool(bool),
    /// Integer with its scalar type (`i32`, `u32`, `u64` or abstract); the value itself, so
    /// wide enough for every `u64`.
    Int(i128, Scalar),
    /// Float with its scalar type (`f32` or abstract).
    Float(f64, Scalar),
}

/// Unary operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnOp {
    /// `-x`
    Neg,
    /// `!b` on booleans
    Not,
    /// `!x` on integers (WGSL `~`)
    BitNot,
}

/// Binary operators (the WGSL operator has the same spelling).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Rem,
    BitAnd,
    BitOr,
    BitXor,
    Shl,
    Shr,
    And,
    Or,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

impl BinOp {
    /// WGSL (and Rust) spelling.
    pub fn symbol(self) -> &'static str {
        use BinOp::*;
        match self {
            Add => "+",
            Sub => "-",
            Mul => "*",
            Div => "/",
            Rem => "%",
            BitAnd => "&",
            BitOr => "|",
            BitXor => "^",
            Shl => "<<",
            Shr => ">>",
            And => "&&",
            Or => "||",
            Eq => "==",
            Ne => "!=",
            Lt => "<",
            Le => "<=",
            Gt => ">",
            Ge => ">=",
        }
    }

    /// Comparison operators (result `bool`).
    pub fn is_comparison(self) -> bool {
        use BinOp::*;
        matches!(self, Eq | Ne | Lt | Le | Gt | Ge)
    }
}

/// A call to a WGSL builtin function, with arguments already in WGSL order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Builtin {
    /// WGSL function name.
    pub wgsl: &'static str,
    /// Needs the SUBGROUP capability.
    pub subgroup: bool,
    /// The first argument is passed by pointer (`&place`): atomics.
    pub pointer_first: bool,
}

/// Expression kinds.
#[derive(Debug, Clone)]
pub enum ExprKind {
    /// A literal.
    Lit(Lit),
    /// A local variable or parameter (index into `Function::locals`).
    Local(usize),
    /// A `static` (index into `Module::globals`).
    Global(usize),
    /// A `const` (index into `Module::consts`).
    Const(usize),
    /// An axis (index into `Module::axes`), replaced by its value per variant.
    Axis(usize),
    /// Unary operation.
    Unary(UnOp, Box<Expr>),
    /// Binary operation.
    Binary(BinOp, Box<Expr>, Box<Expr>),
    /// `x as T` (the target is the expression's type).
    Cast(Box<Expr>),
    /// Struct field access (index into the struct's fields).
    Field(Box<Expr>, usize),
    /// Vector component access or swizzle, e.g. `x`, `xy`, `zyx`.
    Swizzle(Box<Expr>, String),
    /// `base[index]`
    Index(Box<Expr>, Box<Expr>),
    /// Constructor of the expression's type (vectors, matrices, structs, arrays).
    Construct(Vec<Expr>),
    /// Call of a module function (index into `Module::functions`).
    Call(usize, Vec<Expr>),
    /// Call of a WGSL builtin function.
    Builtin(Builtin, Vec<Expr>),
    /// `&mut place` argument: WGSL `&place`.
    AddrOf(Box<Expr>),
    /// `*ptr`
    Deref(Box<Expr>),
}

/// A typed expression.
#[derive(Debug, Clone)]
pub struct Expr {
    /// What it is.
    pub kind: ExprKind,
    /// Its type.
    pub ty: Ty,
    /// The Rust source it came from.
    pub span: Span,
}

/// A block of statements.
pub type Block = Vec<Stmt>;

/// Statements.
#[derive(Debug, Clone)]
pub enum Stmt {
    /// `let` / `let mut` (local index); `None` local for `let _ = e;`.
    Let {
        /// The local, `None` for `_`.
        local: Option<usize>,
        /// Initializer.
        init: Expr,
        /// Span of the statement.
        span: Span,
    },
    /// `place = value` or `place op= value`.
    Assign {
        /// Target.
        place: Expr,
        /// Compound operator.
        op: Option<BinOp>,
        /// Value.
        value: Expr,
        /// Span.
        span: Span,
    },
    /// An expression statement (a call).
    Expr(Expr),
    /// `if`/`else`.
    If {
        /// Condition.
        cond: Expr,
        /// Then branch.
        then: Block,
        /// Else branch (an `else if` is a block with one `If`).
        els: Option<Block>,
        /// Span of the `if` keyword.
        span: Span,
    },
    /// `for var in start..end` / `start..=end`.
    For {
        /// Loop variable.
        var: usize,
        /// Start.
        start: Expr,
        /// End.
        end: Expr,
        /// `..=`
        inclusive: bool,
        /// Body.
        body: Block,
        /// Span.
        span: Span,
    },
    /// `while cond { .. }`
    While {
        /// Condition.
        cond: Expr,
        /// Body.
        body: Block,
        /// Span.
        span: Span,
    },
    /// `loop { .. }`
    Loop {
        /// Body.
        body: Block,
        /// Span.
        span: Span,
    },
    /// `break`
    Break(Span),
    /// `continue`
    Continue(Span),
    /// `return` (also a function's tail expression).
    Return(Option<Expr>, Span),
    /// `discard()`: ends a fragment invocation without output.
    Discard(Span),
    /// A nested `{ .. }` block.
    Block(Block),
}

/// An unevaluated array length (compares equal to any other length).
#[derive(Debug, Clone)]
pub struct ArrayLen(pub Box<Expr>);

impl PartialEq for ArrayLen {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// A type of the DSL.
#[derive(Debug, Clone, PartialEq)]
pub enum Ty {
    /// `()`
    Unit,
    /// Scalars.
    Scalar(Scalar),
    /// `Vec2`..`Vec4`, `UVec*`, `IVec*`, `BVec*`.
    Vector(u8, Scalar),
    /// `Mat3`, `Mat4` (columns, rows), always `f32`.
    Matrix(u8, u8),
    /// `[T; N]`
    Array(Box<Ty>, ArrayLen),
    /// `[T]` (storage buffers only)
    RuntimeArray(Box<Ty>),
    /// A DSL struct.
    Struct(StructId),
    /// `Atomic<u32>` / `Atomic<i32>` / `Atomic<u64>` (storage only, `fetch_min`/`fetch_max`)
    Atomic(Scalar),
    /// Sampled and depth textures.
    Texture(TextureTy),
    /// `StorageTexture2d<Format, Access>`
    StorageTexture(StorageFormatTy, Access),
    /// `Sampler` / `SamplerComparison`
    Sampler {
        /// Comparison sampler.
        comparison: bool,
    },
    /// `&mut T` parameter.
    Ptr(Box<Ty>),
}

impl Ty {
    /// Shorthand for `f32`.
    pub const F32: Ty = Ty::Scalar(Scalar::F32);
    /// Shorthand for `u32`.
    pub const U32: Ty = Ty::Scalar(Scalar::U32);
    /// Shorthand for `i32`.
    pub const I32: Ty = Ty::Scalar(Scalar::I32);
    /// Shorthand for `bool`.
    pub const BOOL: Ty = Ty::Scalar(Scalar::Bool);
    /// Shorthand for `u64`.
    pub const U64: Ty = Ty::Scalar(Scalar::U64);

    /// The scalar of a scalar or vector type.
    pub fn scalar(&self) -> Option<Scalar> {
        match self {
            Ty::Scalar(s) | Ty::Vector(_, s) => Some(*s),
            Ty::Matrix(..) => Some(Scalar::F32),
            _ => None,
        }
    }

    /// Scalar or vector of floats.
    pub fn is_float_like(&self) -> bool {
        matches!(self, Ty::Scalar(s) | Ty::Vector(_, s) if s.is_float())
    }

    /// Scalar or vector of integers.
    pub fn is_int_like(&self) -> bool {
        matches!(self, Ty::Scalar(s) | Ty::Vector(_, s) if s.is_int())
    }

    /// Scalar or vector of numbers.
    pub fn is_numeric(&self) -> bool {
        matches!(self, Ty::Scalar(s) | Ty::Vector(_, s) if s.is_numeric())
    }

    /// Replaces abstract scalars by the types a `let` would give them.
    pub fn concretize(&self) -> Ty {
        match self {
            Ty::Scalar(s) => Ty::Scalar(s.concretize()),
            Ty::Vector(n, s) => Ty::Vector(*n, s.concretize()),
            t => t.clone(),
        }
    }

    /// The common type of two types under literal conversion, if any.
    pub fn unify(&self, other: &Ty) -> Option<Ty> {
        match (self, other) {
            (Ty::Scalar(a), Ty::Scalar(b)) => a.unify(*b).map(Ty::Scalar),
            (Ty::Vector(n, a), Ty::Vector(m, b)) if n == m => {
                a.unify(*b).map(|s| Ty::Vector(*n, s))
            }
            (a, b) if a == b => Some(a.clone()),
            _ => None,
        }
    }

    /// Whether a value of type `self` may be stored where `target` is expected.
    pub fn converts_to(&self, target: &Ty) -> bool {
        self.unify(target).as_ref() == Some(target)
    }

    /// Whether values of this type can be host-shared (uniform/storage buffers).
    pub fn is_constructible(&self) -> bool {
        !matches!(
            self,
            Ty::Texture(_)
                | Ty::StorageTexture(..)
                | Ty::Sampler { .. }
                | Ty::Ptr(_)
                | Ty::Atomic(_)
                | Ty::RuntimeArray(_)
                | Ty::Unit
        )
    }
}
