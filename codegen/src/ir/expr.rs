//! IR expressions and statements. Every expression carries its type and source span.

use super::Ty;
use proc_macro2::Span;

/// A literal value (also the value of an axis).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Lit {
    /// `true` / `false`
    Bool(bool),
    /// Integer with its scalar type (`i32`, `u32` or abstract).
    Int(i64, super::Scalar),
    /// Float with its scalar type (`f32` or abstract).
    Float(f64, super::Scalar),
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
