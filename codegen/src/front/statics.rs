//! Lowers `static` items: resource kind and type checks, `#[when(..)]` predicates and
//! binding conflicts.

use super::args::BareStatic;
use super::attrs::{self, StaticKind};
use super::ctx::register;
use super::ctx::{FnCtx, ModCtx};
use super::types::TyPos;
use crate::ir::{self, Scalar, Space, Ty};
use syn::spanned::Spanned;
use syn::{Error, Result};

pub(crate) fn lower_static(m: &mut ModCtx, st: &BareStatic) -> Result<()> {
    let attr = attrs::static_attr(&st.attrs, st.ident.span())?;
    if st.mutability {
        return Err(Error::new(
            st.ident.span(),
            "`static mut` is not needed: mutability comes from `#[storage(.., read_write)]` or `#[workgroup]`",
        ));
    }
    if let Some(span) = st.value {
        return Err(Error::new(
            span,
            "bindings and workgroup variables have no initializer; write `static NAME: Type;`",
        ));
    }
    let ty = FnCtx::new(m, true).lower_type(&st.ty, TyPos::Static)?;
    let tyname = FnCtx::new(m, true).ty_name(&ty);
    let bad = |what: &str| Error::new(st.ty.span(), format!("`{tyname}` cannot be {what}"));
    let space = match attr.kind {
        StaticKind::Uniform => {
            if vec3_array(&ty) {
                return Err(Error::new(st.ty.span(), VEC3_ARRAY));
            }
            if !ty.is_constructible() || matches!(ty, Ty::Scalar(Scalar::Bool)) {
                return Err(bad(
                    "a uniform buffer; use a struct, scalar, vector, matrix or array",
                ));
            }
            Space::Uniform
        }
        StaticKind::Storage => {
            if vec3_array(&ty) {
                return Err(Error::new(st.ty.span(), VEC3_ARRAY));
            }
            let ok = match &ty {
                Ty::RuntimeArray(_) | Ty::Atomic(_) => true,
                Ty::Array(e, _) if matches!(**e, Ty::Atomic(_)) => true,
                t => t.is_constructible(),
            };
            if !ok {
                return Err(bad("a storage buffer"));
            }
            if !attr.read_write && contains_atomic(&ty, &m.module) {
                return Err(Error::new(
                    attr.span,
                    "storage buffers with atomics must be `read_write`",
                ));
            }
            Space::Storage {
                read_write: attr.read_write,
            }
        }
        StaticKind::Texture => {
            if !matches!(ty, Ty::Texture(_) | Ty::StorageTexture(..)) {
                return Err(bad(
                    "a `#[texture]`; use a `Texture*` or `StorageTexture2d` type",
                ));
            }
            Space::Handle
        }
        StaticKind::Sampler => {
            if !matches!(ty, Ty::Sampler { .. }) {
                return Err(bad("a `#[sampler]`; use `Sampler` or `SamplerComparison`"));
            }
            Space::Handle
        }
        StaticKind::Workgroup => {
            if contains_atomic64(&ty, &m.module) {
                return Err(Error::new(st.ty.span(), ATOMIC64_WORKGROUP));
            }
            let ok = match &ty {
                Ty::Atomic(_) => true,
                Ty::Array(e, _) if matches!(**e, Ty::Atomic(_)) => true,
                t => t.is_constructible(),
            };
            if !ok {
                return Err(bad(
                    "a workgroup variable; use a sized value type, an atomic or a fixed-size array",
                ));
            }
            Space::Workgroup
        }
    };
    let when = match &attr.when {
        None => None,
        Some(e) => {
            let p = FnCtx::new(m, true).const_expr(e)?;
            if p.ty != Ty::BOOL {
                return Err(Error::new(
                    e.span(),
                    "`#[when(..)]` takes a `bool` predicate over axes",
                ));
            }
            Some(p)
        }
    };
    if let Some(gb) = attr.group_binding
        && let Some(other) = m
            .module
            .globals
            .iter()
            .find(|g| g.binding == Some(gb) && g.when.is_none() && when.is_none())
    {
        return Err(Error::new(
            attr.span,
            format!(
                "binding conflict: `group = {}, binding = {}` is already used by `{}`",
                gb.0, gb.1, other.name
            ),
        ));
    }
    register(m, &st.ident, "static")?;
    m.global_ids
        .insert(st.ident.to_string(), m.module.globals.len());
    m.module.globals.push(ir::Global {
        name: st.ident.to_string(),
        ty,
        space,
        binding: attr.group_binding,
        unfilterable: attr.unfilterable,
        when,
        from_library: m.origin.is_some(),
        span: st.ident.span(),
    });
    Ok(())
}

fn contains_atomic(ty: &Ty, m: &ir::Module) -> bool {
    contains(ty, m, &|s| matches!(s, Ty::Atomic(_)))
}

fn contains_atomic64(ty: &Ty, m: &ir::Module) -> bool {
    contains(ty, m, &|s| *s == Ty::Atomic(Scalar::U64))
}

/// Whether `ty` is, or holds (in arrays and struct fields), a type `leaf` accepts.
fn contains(ty: &Ty, m: &ir::Module, leaf: &dyn Fn(&Ty) -> bool) -> bool {
    leaf(ty)
        || match ty {
            Ty::Array(e, _) | Ty::RuntimeArray(e) => contains(e, m, leaf),
            Ty::Struct(id) => m.structs[*id]
                .fields
                .iter()
                .any(|f| contains(&f.ty, m, leaf)),
            _ => false,
        }
}

const ATOMIC64_WORKGROUP: &str = "`Atomic<u64>` lives only in `#[storage(.., read_write)]` buffers: the device's 64-bit atomics (wgpu's SHADER_INT64_ATOMIC_MIN_MAX) are `fetch_min`/`fetch_max` on storage buffers; use `Atomic<u32>` in workgroup memory";

pub(crate) const VEC3_ARRAY: &str = "arrays of 3-component vectors have a 16-byte stride on the GPU but 12 bytes on the host (glam `Vec3`), so buffers of them are a layout trap; use `[Vec4]`/`[UVec4]`, or a struct with a `Vec3` and a scalar";

/// Arrays (sized or not) whose element is a 3-component vector.
pub(crate) fn vec3_array(ty: &Ty) -> bool {
    matches!(ty, Ty::Array(e, _) | Ty::RuntimeArray(e) if matches!(**e, Ty::Vector(3, _)))
}
