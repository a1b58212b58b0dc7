//! The generated expression tree: typed nodes that print as DSL (Rust-syntax) source.

use std::fmt::Write as _;

/// A scalar type of the generated language.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Sc {
    /// `i32`
    I32,
    /// `u32`
    U32,
    /// `f32`
    F32,
    /// `bool`
    Bool,
}

impl Sc {
    /// Every scalar.
    pub const ALL: [Sc; 4] = [Sc::I32, Sc::U32, Sc::F32, Sc::Bool];

    /// Rust spelling.
    pub fn name(self) -> &'static str {
        match self {
            Sc::I32 => "i32",
            Sc::U32 => "u32",
            Sc::F32 => "f32",
            Sc::Bool => "bool",
        }
    }

    /// glam vector prefix.
    pub fn prefix(self) -> &'static str {
        match self {
            Sc::I32 => "I",
            Sc::U32 => "U",
            Sc::F32 => "",
            Sc::Bool => "B",
        }
    }
}

/// A scalar (`n == 1`) or vector type.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct T {
    /// Components: 1 for a scalar, 2 to 4 for a vector.
    pub n: u8,
    /// Scalar type.
    pub s: Sc,
}

impl T {
    /// A scalar type.
    pub const fn scalar(s: Sc) -> T {
        T { n: 1, s }
    }

    /// The DSL spelling (`u32`, `IVec3`).
    pub fn name(self) -> String {
        if self.n == 1 {
            self.s.name().into()
        } else {
            format!("{}Vec{}", self.s.prefix(), self.n)
        }
    }
}

/// How closely the GPU must match the host for a float result (see [`super`] for the table).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tol {
    /// Equal as `f32` values (`-0.0 == 0.0`); integers and bools are always compared exactly.
    Exact,
    /// At most this many units in the last place apart.
    Ulp(u32),
    /// At most this absolute difference.
    Abs(f32),
    /// Within this many ULPs, or this absolute difference.
    UlpOrAbs(u32, f32),
}

/// A node of a generated expression.
#[derive(Debug, Clone, PartialEq)]
pub enum Kind {
    /// An input local: `i0`, `u2`, `f1`, `b3`.
    Input(usize),
    /// A variable of a statement program (`p0s1`, `p0v0.y`, `p0a0[2]`), as source text.
    Var(String),
    /// A literal, as DSL source text.
    Lit(String),
    /// A prefix operator (`-`, `!`).
    Un(&'static str, Box<E>),
    /// A binary operator.
    Bin(&'static str, Box<E>, Box<E>),
    /// `(x as T)`.
    Cast(Box<E>),
    /// `recv.method(args)`.
    Method(&'static str, Box<E>, Vec<E>),
    /// `select(c, t, f)`.
    Select(Box<E>, Box<E>, Box<E>),
    /// `Vec3::new(..)` (components may be vectors).
    New(Vec<E>),
    /// `Vec3::splat(x)`.
    Splat(Box<E>),
    /// `v.zyx()` or `v.x`.
    Swizzle(Box<E>, String),
    /// `v[(i % N)]` with `i: u32`.
    Index(Box<E>, Box<E>),
    /// `v.as_uvec3()` and friends.
    AsVec(Box<E>),
}

/// A typed expression node.
#[derive(Debug, Clone, PartialEq)]
pub struct E {
    /// Its type.
    pub ty: T,
    /// What it is.
    pub kind: Kind,
}

/// Names of the input locals of one scalar type: 4 per type.
pub const INPUTS_PER_TYPE: usize = 4;

impl E {
    /// The children, in order.
    pub fn children(&self) -> Vec<&E> {
        match &self.kind {
            Kind::Input(_) | Kind::Var(_) | Kind::Lit(_) => vec![],
            Kind::Un(_, a)
            | Kind::Cast(a)
            | Kind::Splat(a)
            | Kind::Swizzle(a, _)
            | Kind::AsVec(a) => {
                vec![a]
            }
            Kind::Bin(_, a, b) | Kind::Index(a, b) => vec![a, b],
            Kind::Select(a, b, c) => vec![a, b, c],
            Kind::Method(_, r, args) => std::iter::once(&**r).chain(args).collect(),
            Kind::New(args) => args.iter().collect(),
        }
    }

    /// Mutable children, in the order of [`E::children`].
    pub fn children_mut(&mut self) -> Vec<&mut E> {
        match &mut self.kind {
            Kind::Input(_) | Kind::Var(_) | Kind::Lit(_) => vec![],
            Kind::Un(_, a)
            | Kind::Cast(a)
            | Kind::Splat(a)
            | Kind::Swizzle(a, _)
            | Kind::AsVec(a) => {
                vec![a]
            }
            Kind::Bin(_, a, b) | Kind::Index(a, b) => vec![a, b],
            Kind::Select(a, b, c) => vec![a, b, c],
            Kind::Method(_, r, args) => std::iter::once(&mut **r).chain(args.iter_mut()).collect(),
            Kind::New(args) => args.iter_mut().collect(),
        }
    }

    /// Number of nodes.
    pub fn size(&self) -> usize {
        1 + self.children().iter().map(|c| c.size()).sum::<usize>()
    }

    /// Whether an input local occurs in it (a tree without one would be constant-folded by
    /// naga, which rejects constant overflow).
    pub fn has_input(&self) -> bool {
        matches!(self.kind, Kind::Input(_) | Kind::Var(_))
            || self.children().iter().any(|c| c.has_input())
    }

    /// DSL source text.
    pub fn source(&self) -> String {
        let mut s = String::new();
        self.write(&mut s);
        s
    }

    fn write(&self, o: &mut String) {
        match &self.kind {
            Kind::Input(i) => {
                let p = match self.ty.s {
                    Sc::I32 => 'i',
                    Sc::U32 => 'u',
                    Sc::F32 => 'f',
                    Sc::Bool => 'b',
                };
                let _ = write!(o, "{p}{i}");
            }
            Kind::Lit(l) | Kind::Var(l) => o.push_str(l),
            Kind::Un(op, a) => {
                let _ = write!(o, "({op}");
                a.write(o);
                o.push(')');
            }
            Kind::Bin(op, a, b) => {
                o.push('(');
                a.write(o);
                let _ = write!(o, " {op} ");
                b.write(o);
                o.push(')');
            }
            Kind::Cast(a) => {
                o.push('(');
                a.write(o);
                let _ = write!(o, " as {})", self.ty.s.name());
            }
            Kind::Method(m, r, args) => {
                r.write(o);
                let _ = write!(o, ".{m}(");
                for (i, a) in args.iter().enumerate() {
                    if i > 0 {
                        o.push_str(", ");
                    }
                    a.write(o);
                }
                o.push(')');
            }
            Kind::Select(c, t, f) => {
                o.push_str("select(");
                c.write(o);
                o.push_str(", ");
                t.write(o);
                o.push_str(", ");
                f.write(o);
                o.push(')');
            }
            Kind::New(args) => {
                let _ = write!(o, "{}::new(", self.ty.name());
                for (i, a) in args.iter().enumerate() {
                    if i > 0 {
                        o.push_str(", ");
                    }
                    a.write(o);
                }
                o.push(')');
            }
            Kind::Splat(a) => {
                let _ = write!(o, "{}::splat(", self.ty.name());
                a.write(o);
                o.push(')');
            }
            Kind::Swizzle(a, s) => {
                a.write(o);
                if s.len() == 1 {
                    let _ = write!(o, ".{s}");
                } else {
                    let _ = write!(o, ".{s}()");
                }
            }
            Kind::Index(v, i) => {
                v.write(o);
                o.push_str("[(");
                i.write(o);
                let _ = write!(o, " % {}u32)]", v.ty.n);
            }
            Kind::AsVec(a) => {
                a.write(o);
                let _ = write!(
                    o,
                    ".as_{}vec{}()",
                    self.ty.s.prefix().to_lowercase(),
                    self.ty.n
                );
            }
        }
    }
}
