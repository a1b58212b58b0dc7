//! Lowers Rust type syntax to IR types and names IR types for error messages.
//!
//! Accepts only GPU types (scalars, glam vectors and matrices, arrays, DSL structs, atomics,
//! textures, samplers); everything else gets an error that says what to use instead.

use super::ctx::FnCtx;
use crate::ir::{Access, ArrayLen, Module, Scalar, StorageFormatTy, TexKind, TextureTy, Ty};
use syn::spanned::Spanned;
use syn::{Error, Result};

/// Where a type appears, which decides what is allowed.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum TyPos {
    /// Struct field, local, const, return: sized value types.
    Value,
    /// `static` item: also runtime-sized arrays, textures, samplers, atomics.
    Static,
    /// Function parameter: also `&mut T`.
    Param,
    /// Struct field: also atomics.
    Field,
}

const FORMATS: &[(&str, &str, Scalar)] = &[
    ("Rgba8Unorm", "rgba8unorm", Scalar::F32),
    ("Rgba8Snorm", "rgba8snorm", Scalar::F32),
    ("Rgba8Uint", "rgba8uint", Scalar::U32),
    ("Rgba8Sint", "rgba8sint", Scalar::I32),
    ("Rgba16Uint", "rgba16uint", Scalar::U32),
    ("Rgba16Sint", "rgba16sint", Scalar::I32),
    ("Rgba16Float", "rgba16float", Scalar::F32),
    ("R32Uint", "r32uint", Scalar::U32),
    ("R32Sint", "r32sint", Scalar::I32),
    ("R32Float", "r32float", Scalar::F32),
    ("Rg32Uint", "rg32uint", Scalar::U32),
    ("Rg32Sint", "rg32sint", Scalar::I32),
    ("Rg32Float", "rg32float", Scalar::F32),
    ("Rgba32Uint", "rgba32uint", Scalar::U32),
    ("Rgba32Sint", "rgba32sint", Scalar::I32),
    ("Rgba32Float", "rgba32float", Scalar::F32),
    ("Bgra8Unorm", "bgra8unorm", Scalar::F32),
];

/// Resolves a scalar type name.
pub(crate) fn scalar_named(name: &str) -> Option<Scalar> {
    Some(match name {
        "f32" => Scalar::F32,
        "u32" => Scalar::U32,
        "i32" => Scalar::I32,
        "u64" => Scalar::U64,
        "bool" => Scalar::Bool,
        _ => return None,
    })
}

/// Resolves a glam vector or matrix name (`Vec3`, `UVec2`, `Mat4`).
pub(crate) fn vec_or_mat_named(name: &str) -> Option<Ty> {
    if let Some(n) = name.strip_prefix("Mat") {
        return match n {
            "2" => Some(Ty::Matrix(2, 2)),
            "3" => Some(Ty::Matrix(3, 3)),
            "4" => Some(Ty::Matrix(4, 4)),
            _ => None,
        };
    }
    let (scalar, rest) = match name.as_bytes().first()? {
        b'U' => (Scalar::U32, &name[1..]),
        b'I' => (Scalar::I32, &name[1..]),
        b'B' => (Scalar::Bool, &name[1..]),
        _ => (Scalar::F32, name),
    };
    match rest {
        "Vec2" => Some(Ty::Vector(2, scalar)),
        "Vec3" => Some(Ty::Vector(3, scalar)),
        "Vec4" => Some(Ty::Vector(4, scalar)),
        _ => None,
    }
}

fn hint_for(name: &str) -> Option<&'static str> {
    Some(match name {
        "Vec" | "String" | "Box" | "Rc" | "Arc" | "HashMap" | "BTreeMap" | "VecDeque" => {
            "heap types are not available on the GPU; use a fixed-size array `[T; N]`, or a runtime-sized storage buffer `static NAME: [T];`"
        }
        "i64" => {
            "the DSL's only 64-bit integer is `u64` (needs wgpu's SHADER_INT64); use `u64` or `i32`"
        }
        "usize" | "isize" | "u8" | "u16" | "i8" | "i16" | "u128" | "i128" => {
            "this integer type is not a GPU type; use `u32` or `i32`"
        }
        "U64Vec2" | "U64Vec3" | "U64Vec4" | "I64Vec2" | "I64Vec3" | "I64Vec4" => {
            "the DSL has no vectors of 64-bit integers; use one `u64` per component"
        }
        "f64" | "f16" => "use `f32`: it is the only float type of the DSL",
        "Option" | "Result" => {
            "`Option` and `Result` are not available on the GPU; use a flag or a sentinel value"
        }
        "Vec3A" | "Mat3A" => "use `Vec3`/`Mat3`: the DSL applies GPU alignment itself",
        _ => return None,
    })
}

impl FnCtx<'_> {
    /// Lowers a type in the given position.
    pub(crate) fn lower_type(&mut self, ty: &syn::Type, pos: TyPos) -> Result<Ty> {
        match ty {
            syn::Type::Paren(p) => self.lower_type(&p.elem, pos),
            syn::Type::Tuple(t) if t.elems.is_empty() => Ok(Ty::Unit),
            syn::Type::Array(a) => {
                let elem = self.lower_type(&a.elem, TyPos::Field)?;
                if !elem.is_constructible() && !matches!(elem, Ty::Atomic(_)) {
                    return Err(Error::new(
                        a.elem.span(),
                        "arrays hold only sized value types or atomics",
                    ));
                }
                let len = self.const_expr(&a.len)?;
                if !len.ty.scalar().is_some_and(|s| s.is_int32())
                    || !matches!(len.ty, Ty::Scalar(_))
                {
                    return Err(Error::new(
                        a.len.span(),
                        "array length must be a `u32` or `i32` constant",
                    ));
                }
                Ok(Ty::Array(Box::new(elem), ArrayLen(Box::new(len))))
            }
            syn::Type::Slice(s) => {
                if pos != TyPos::Static {
                    return Err(Error::new(
                        ty.span(),
                        "runtime-sized arrays `[T]` are only allowed as the type of a `#[storage]` static",
                    ));
                }
                let elem = self.lower_type(&s.elem, TyPos::Field)?;
                Ok(Ty::RuntimeArray(Box::new(elem)))
            }
            syn::Type::Reference(r) => {
                if pos != TyPos::Param {
                    return Err(Error::new(
                        ty.span(),
                        "references are only allowed as `&mut T` parameters of helper functions (in-out arguments); store values instead",
                    ));
                }
                if r.mutability.is_none() {
                    return Err(Error::new(
                        ty.span(),
                        "shared references are not supported; pass the value itself, or `&mut T` for an in-out argument",
                    ));
                }
                let inner = self.lower_type(&r.elem, TyPos::Value)?;
                Ok(Ty::Ptr(Box::new(inner)))
            }
            syn::Type::Path(p) if p.qself.is_none() => self.lower_path_type(p, pos),
            syn::Type::ImplTrait(_) | syn::Type::TraitObject(_) => Err(Error::new(
                ty.span(),
                "trait objects and `impl Trait` are not supported; generics that are not axes are not allowed",
            )),
            _ => Err(Error::new(
                ty.span(),
                "unsupported type in shader code; use scalars, glam vectors/matrices, arrays or DSL structs",
            )),
        }
    }

    fn lower_path_type(&mut self, p: &syn::TypePath, pos: TyPos) -> Result<Ty> {
        #[expect(
            clippy::expect_used,
            reason = "syn never parses a path without segments"
        )]
        let seg = p.path.segments.last().expect("a path has a segment");
        let name = seg.ident.to_string();
        let span = seg.ident.span();
        let generic_args: Vec<&syn::Type> = match &seg.arguments {
            syn::PathArguments::None => vec![],
            syn::PathArguments::AngleBracketed(a) => a
                .args
                .iter()
                .map(|g| match g {
                    syn::GenericArgument::Type(t) => Ok(t),
                    other => Err(Error::new(other.span(), "expected a type argument")),
                })
                .collect::<Result<_>>()?,
            syn::PathArguments::Parenthesized(a) => {
                return Err(Error::new(a.span(), "unsupported type"));
            }
        };
        let no_args = |ty: Ty| -> Result<Ty> {
            if generic_args.is_empty() {
                Ok(ty)
            } else {
                Err(Error::new(
                    seg.arguments.span(),
                    format!("`{name}` takes no type arguments"),
                ))
            }
        };
        if let Some(s) = scalar_named(&name) {
            return no_args(Ty::Scalar(s));
        }
        if let Some(t) = vec_or_mat_named(&name) {
            return no_args(t);
        }
        if let Some(&id) = self.m.struct_ids.get(&name) {
            return no_args(Ty::Struct(id));
        }
        let handle_only = |ty: Ty| -> Result<Ty> {
            if pos == TyPos::Static {
                Ok(ty)
            } else {
                Err(Error::new(
                    span,
                    format!("`{name}` can only be the type of a `static` binding"),
                ))
            }
        };
        let tex = |kind, arrayed, multisampled| {
            Ty::Texture(TextureTy {
                kind,
                arrayed,
                multisampled,
            })
        };
        let sampled = |args: &[&syn::Type]| -> Result<TexKind> {
            match args {
                [] => Ok(TexKind::Sampled(Scalar::F32)),
                [t] => match t {
                    syn::Type::Path(tp) => match tp
                        .path
                        .get_ident()
                        .and_then(|i| scalar_named(&i.to_string()))
                    {
                        Some(s @ (Scalar::F32 | Scalar::U32 | Scalar::I32)) => {
                            Ok(TexKind::Sampled(s))
                        }
                        _ => Err(Error::new(
                            t.span(),
                            "texel type must be `f32`, `u32` or `i32`",
                        )),
                    },
                    _ => Err(Error::new(
                        t.span(),
                        "texel type must be `f32`, `u32` or `i32`",
                    )),
                },
                _ => Err(Error::new(seg.arguments.span(), "expected one texel type")),
            }
        };
        match name.as_str() {
            "Atomic" => {
                if !matches!(pos, TyPos::Static | TyPos::Field) {
                    return Err(Error::new(
                        span,
                        "atomics live only in `#[workgroup]`/`#[storage]` statics and struct fields",
                    ));
                }
                let inner = match generic_args.as_slice() {
                    [t] => self.lower_type(t, TyPos::Value)?,
                    _ => Ty::Unit,
                };
                match inner {
                    Ty::Scalar(s @ (Scalar::U32 | Scalar::I32 | Scalar::U64)) => Ok(Ty::Atomic(s)),
                    _ => Err(Error::new(
                        seg.arguments.span(),
                        "expected `Atomic<u32>`, `Atomic<i32>` or `Atomic<u64>`",
                    )),
                }
            }
            "Texture2d" => handle_only(tex(sampled(&generic_args)?, false, false)),
            "Texture2dArray" => handle_only(tex(sampled(&generic_args)?, true, false)),
            "TextureMultisampled2d" => handle_only(tex(sampled(&generic_args)?, false, true)),
            "TextureDepth2d" => no_args(tex(TexKind::Depth, false, false)).and_then(handle_only),
            "TextureDepth2dArray" => {
                no_args(tex(TexKind::Depth, true, false)).and_then(handle_only)
            }
            "TextureDepthMultisampled2d" => {
                no_args(tex(TexKind::Depth, false, true)).and_then(handle_only)
            }
            "Sampler" => no_args(Ty::Sampler { comparison: false }).and_then(handle_only),
            "SamplerComparison" => no_args(Ty::Sampler { comparison: true }).and_then(handle_only),
            "StorageTexture2d" => {
                let [fmt, access] = generic_args.as_slice() else {
                    return Err(Error::new(
                        span,
                        "expected `StorageTexture2d<Format, Read|Write|ReadWrite>`",
                    ));
                };
                let fname = quote::ToTokens::to_token_stream(fmt).to_string();
                let format = FORMATS.iter().find(|f| f.0 == fname).ok_or_else(|| {
                    let list: Vec<_> = FORMATS.iter().map(|f| f.0).collect();
                    Error::new(
                        fmt.span(),
                        format!(
                            "unknown storage texture format; expected one of: {}",
                            list.join(", ")
                        ),
                    )
                })?;
                let access = match quote::ToTokens::to_token_stream(access)
                    .to_string()
                    .as_str()
                {
                    "Read" => Access::Read,
                    "Write" => Access::Write,
                    "ReadWrite" => Access::ReadWrite,
                    _ => {
                        return Err(Error::new(
                            access.span(),
                            "expected `Read`, `Write` or `ReadWrite`",
                        ));
                    }
                };
                let f = StorageFormatTy {
                    rust: format.0,
                    wgsl: format.1,
                    scalar: format.2,
                };
                handle_only(Ty::StorageTexture(f, access))
            }
            _ => {
                let msg = match hint_for(&name) {
                    Some(h) => format!("`{name}` is not supported in shader code: {h}"),
                    None if self.m.module.axis(&name).is_some() => {
                        format!("`{name}` is an axis value, not a type")
                    }
                    None => format!(
                        "unknown type `{name}`; generics that are not axes are not supported, and types must be scalars, glam vectors/matrices, arrays or structs of this module"
                    ),
                };
                Err(Error::new(span, msg))
            }
        }
    }
}

/// Names a type the way the user wrote it, for error messages.
pub(crate) fn ty_name(ty: &Ty, m: &Module) -> String {
    match ty {
        Ty::Unit => "()".into(),
        Ty::Scalar(s) => s.rust_name().into(),
        Ty::Vector(n, s) => format!("{}Vec{n}", s.vec_prefix()),
        Ty::Matrix(c, _) => format!("Mat{c}"),
        Ty::Array(t, _) => format!("[{}; N]", ty_name(t, m)),
        Ty::RuntimeArray(t) => format!("[{}]", ty_name(t, m)),
        Ty::Struct(id) => m.structs[*id].name.clone(),
        Ty::Atomic(s) => format!("Atomic<{}>", s.rust_name()),
        Ty::Texture(t) => match (t.kind, t.multisampled, t.arrayed) {
            (TexKind::Depth, true, _) => "TextureDepthMultisampled2d".to_string(),
            (TexKind::Depth, false, true) => "TextureDepth2dArray".into(),
            (TexKind::Depth, false, false) => "TextureDepth2d".into(),
            (TexKind::Sampled(s), true, _) => format!("TextureMultisampled2d<{}>", s.rust_name()),
            (TexKind::Sampled(s), false, true) => format!("Texture2dArray<{}>", s.rust_name()),
            (TexKind::Sampled(s), false, false) => format!("Texture2d<{}>", s.rust_name()),
        },
        Ty::StorageTexture(f, a) => format!("StorageTexture2d<{}, {a:?}>", f.rust),
        Ty::Sampler { comparison: false } => "Sampler".into(),
        Ty::Sampler { comparison: true } => "SamplerComparison".into(),
        Ty::Ptr(t) => format!("&mut {}", ty_name(t, m)),
    }
}

impl FnCtx<'_> {
    /// The DSL spelling of a type, for messages.
    pub(crate) fn ty_name(&self, ty: &Ty) -> String {
        ty_name(ty, &self.m.module)
    }
}
