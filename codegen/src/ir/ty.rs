//! IR types. Array lengths are unevaluated expressions (they may use axes), so two array types
//! compare equal whatever their lengths: naga checks lengths per variant.

use super::Expr;
use super::StructId;

/// Scalar types, including WGSL's abstract literal types.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Scalar {
    /// `bool`
    Bool,
    /// `i32`
    I32,
    /// `u32`
    U32,
    /// `f32`
    F32,
    /// An unsuffixed integer literal: becomes `i32`, `u32` or `f32` by use.
    AbstractInt,
    /// An unsuffixed float literal: becomes `f32`.
    AbstractFloat,
}

impl Scalar {
    /// The Rust spelling (abstract types read as "integer"/"float").
    pub fn rust_name(self) -> &'static str {
        match self {
            Scalar::Bool => "bool",
            Scalar::I32 => "i32",
            Scalar::U32 => "u32",
            Scalar::F32 => "f32",
            Scalar::AbstractInt => "{integer}",
            Scalar::AbstractFloat => "{float}",
        }
    }

    /// The WGSL spelling of the concrete type.
    pub fn wgsl_name(self) -> &'static str {
        match self {
            Scalar::Bool => "bool",
            Scalar::I32 | Scalar::AbstractInt => "i32",
            Scalar::U32 => "u32",
            Scalar::F32 | Scalar::AbstractFloat => "f32",
        }
    }

    /// The glam prefix of vectors of this scalar (`Vec3`, `UVec3`, `IVec3`, `BVec3`).
    pub fn vec_prefix(self) -> &'static str {
        match self {
            Scalar::Bool => "B",
            Scalar::I32 | Scalar::AbstractInt => "I",
            Scalar::U32 => "U",
            Scalar::F32 | Scalar::AbstractFloat => "",
        }
    }

    /// Integer (concrete or abstract).
    pub fn is_int(self) -> bool {
        matches!(self, Scalar::I32 | Scalar::U32 | Scalar::AbstractInt)
    }

    /// Float (concrete or abstract).
    pub fn is_float(self) -> bool {
        matches!(self, Scalar::F32 | Scalar::AbstractFloat)
    }

    /// Numeric: not `bool`.
    pub fn is_numeric(self) -> bool {
        self != Scalar::Bool
    }

    /// The common type of two scalars under literal conversion, if any.
    pub fn unify(self, other: Scalar) -> Option<Scalar> {
        use Scalar::*;
        match (self, other) {
            (a, b) if a == b => Some(a),
            (AbstractInt, b @ (I32 | U32 | F32 | AbstractFloat))
            | (b @ (I32 | U32 | F32 | AbstractFloat), AbstractInt) => Some(b),
            (AbstractFloat, F32) | (F32, AbstractFloat) => Some(F32),
            _ => None,
        }
    }

    /// The concrete type a `let` gives an abstract literal (`i32`, `f32`).
    pub fn concretize(self) -> Scalar {
        match self {
            Scalar::AbstractInt => Scalar::I32,
            Scalar::AbstractFloat => Scalar::F32,
            s => s,
        }
    }
}

/// An unevaluated array length (compares equal to any other length).
#[derive(Debug, Clone)]
pub struct ArrayLen(pub Box<Expr>);

impl PartialEq for ArrayLen {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// Sampled texture kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TexKind {
    /// Sampled texture with this texel scalar.
    Sampled(Scalar),
    /// Depth texture.
    Depth,
}

/// A sampled or depth texture type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TextureTy {
    /// Texel kind.
    pub kind: TexKind,
    /// `*2dArray`
    pub arrayed: bool,
    /// `*Multisampled*`
    pub multisampled: bool,
}

/// Storage texture access.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// `Read`
    Read,
    /// `Write`
    Write,
    /// `ReadWrite`
    ReadWrite,
}

/// Storage texture format: the DSL name and the WGSL name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StorageFormatTy {
    /// DSL (Rust) name, e.g. `Rgba8Unorm`.
    pub rust: &'static str,
    /// WGSL name, e.g. `rgba8unorm`.
    pub wgsl: &'static str,
    /// Texel scalar type of loads/stores.
    pub scalar: Scalar,
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
    /// `Atomic<u32>` / `Atomic<i32>`
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
