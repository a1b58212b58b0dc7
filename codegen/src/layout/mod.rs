//! WGSL memory layout of DSL types (WGSL §"Memory Layout"), with the uniform address space
//! rules applied to structs used in uniform buffers (`@align(16)`/`@size` on struct and array
//! members). The printer emits the same attributes and the host types copy these offsets;
//! naga's `Layouter` is the independent check (see `emit`).
//!
//! Must not decide where a struct is used (the front end marks that) or emit anything.

use crate::ir::{Module, Scalar, Ty};
use crate::variants::{Env, Value, eval};

/// Size and alignment of a type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Layout {
    /// Size in bytes.
    pub size: u32,
    /// Alignment in bytes.
    pub align: u32,
}

/// Layout of one struct member.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MemberLayout {
    /// Offset in bytes.
    pub offset: u32,
    /// Natural layout of the member's type.
    pub ty: Layout,
    /// `@align(n)` to print, when the uniform rules raise the alignment.
    pub align_attr: Option<u32>,
    /// `@size(n)` to print, when the uniform rules raise the size.
    pub size_attr: Option<u32>,
}

/// Layout of a struct.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StructLayout {
    /// Whole struct.
    pub layout: Layout,
    /// Per field.
    pub members: Vec<MemberLayout>,
}

/// Rounds `n` up to a multiple of `align`.
pub fn round_up(n: u32, align: u32) -> u32 {
    n.div_ceil(align) * align
}

/// Evaluates an array length.
pub fn array_len(len: &crate::ir::ArrayLen, m: &Module, env: &Env) -> Option<u32> {
    match eval(&len.0, m, env) {
        Some(Value::Int(n)) if n > 0 => u32::try_from(n).ok(),
        _ => None,
    }
}

/// The natural WGSL layout of a type (runtime arrays: one element).
pub fn layout_of(ty: &Ty, m: &Module, env: &Env) -> Layout {
    match ty {
        Ty::Scalar(Scalar::U64) | Ty::Atomic(Scalar::U64) => Layout { size: 8, align: 8 },
        Ty::Scalar(_) | Ty::Atomic(_) => Layout { size: 4, align: 4 },
        Ty::Vector(n, _) => match n {
            2 => Layout { size: 8, align: 8 },
            3 => Layout {
                size: 12,
                align: 16,
            },
            _ => Layout {
                size: 16,
                align: 16,
            },
        },
        Ty::Matrix(c, r) => {
            let col = layout_of(&Ty::Vector(*r, Scalar::F32), m, env);
            Layout {
                size: u32::from(*c) * round_up(col.size, col.align),
                align: col.align,
            }
        }
        Ty::Array(t, len) => {
            let e = layout_of(t, m, env);
            let n = array_len(len, m, env).unwrap_or(1);
            Layout {
                size: n * round_up(e.size, e.align),
                align: e.align,
            }
        }
        Ty::RuntimeArray(t) => {
            let e = layout_of(t, m, env);
            Layout {
                size: round_up(e.size, e.align),
                align: e.align,
            }
        }
        Ty::Struct(id) => struct_layout(*id, m, env).layout,
        _ => Layout { size: 0, align: 1 },
    }
}

/// The layout of a struct, with uniform rules when the struct is used in a uniform buffer.
pub fn struct_layout(id: usize, m: &Module, env: &Env) -> StructLayout {
    let s = &m.structs[id];
    let uniform = s.uses.uniform;
    let mut offset = 0;
    let mut align = 1;
    let mut members = vec![];
    for f in &s.fields {
        let ty = layout_of(&f.ty, m, env);
        let (mut a, mut size) = (ty.align, ty.size);
        let (mut align_attr, mut size_attr) = (None, None);
        if uniform && matches!(f.ty, Ty::Struct(_) | Ty::Array(..)) && a < 16 {
            a = 16;
            align_attr = Some(16);
        }
        if uniform && matches!(f.ty, Ty::Struct(_)) && size % 16 != 0 {
            size = round_up(size, 16);
            size_attr = Some(size);
        }
        offset = round_up(offset, a);
        members.push(MemberLayout {
            offset,
            ty,
            align_attr,
            size_attr,
        });
        offset += size;
        align = align.max(a);
    }
    StructLayout {
        layout: Layout {
            size: round_up(offset, align),
            align,
        },
        members,
    }
}
