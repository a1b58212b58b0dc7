//! The leaf types of the IR: scalars, texture and storage-texture descriptions, struct ids.
//! Nothing here refers to expressions, so both the type tree and the expressions build on it.

/// Index of a struct in [`super::Module::structs`].
pub type StructId = usize;

/// Scalar types, including WGSL's abstract literal types.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Scalar {
    /// `bool`
    Bool,
    /// `i32`
    I32,
    /// `u32`
    U32,
    /// `u64`: scalars only (no vectors); a variant that uses it needs wgpu's `SHADER_INT64`.
    U64,
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
            Scalar::U64 => "u64",
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
            Scalar::U64 => "u64",
            Scalar::F32 | Scalar::AbstractFloat => "f32",
        }
    }

    /// The glam prefix of vectors of this scalar (`Vec3`, `UVec3`, `IVec3`, `BVec3`; glam's
    /// `U64Vec3`, which the DSL rejects, only in messages).
    pub fn vec_prefix(self) -> &'static str {
        match self {
            Scalar::Bool => "B",
            Scalar::I32 | Scalar::AbstractInt => "I",
            Scalar::U32 => "U",
            Scalar::U64 => "U64",
            Scalar::F32 | Scalar::AbstractFloat => "",
        }
    }

    /// Integer (concrete or abstract, 32 or 64 bits).
    pub fn is_int(self) -> bool {
        matches!(
            self,
            Scalar::I32 | Scalar::U32 | Scalar::U64 | Scalar::AbstractInt
        )
    }

    /// An integer of 32 bits or an abstract one: what indices, array lengths, workgroup sizes,
    /// loop counters, texel coordinates and the DSL's integer builtins take.
    pub fn is_int32(self) -> bool {
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
            (AbstractInt, b @ (I32 | U32 | U64 | F32 | AbstractFloat))
            | (b @ (I32 | U32 | U64 | F32 | AbstractFloat), AbstractInt) => Some(b),
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
