//! Reflection of one variant as plain data: entry points with stage and workgroup size,
//! bindings with visibility and kind, required features. Computed from the IR under the
//! variant's environment; the runtime shapes are in [`crate::rt`], which `emit` turns this into.
//! Must not depend on naga's IR (naga validates; the DSL's own IR is the source of truth).

use crate::ir::{Access, Io, Module, Scalar, Space, Stage, TexKind, Ty};
use crate::layout::layout_of;
use crate::rt::{self, BindingKind, SampleType, StorageAccess, ViewDimension, Visibility};
use crate::variants::{Env, Value, entry_present, eval, used_globals};

/// An entry point.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EntryPointInfo {
    /// Name.
    pub name: String,
    /// Stage.
    pub stage: rt::Stage,
    /// Workgroup size (`[0; 3]` for graphics stages).
    pub workgroup_size: [u32; 3],
    /// Bytes of the workgroup variables it uses, each rounded up to 16.
    pub workgroup_memory: u32,
    /// `#[location]` inputs, sorted by location.
    pub inputs: Vec<rt::Location>,
    /// `#[location]` outputs, sorted by location.
    pub outputs: Vec<rt::Location>,
}

fn value_format(ty: &Ty) -> Option<rt::ValueFormat> {
    use rt::ValueFormat::*;
    let (n, s) = match ty {
        Ty::Scalar(s) => (1, *s),
        Ty::Vector(n, s) => (*n, *s),
        _ => return None,
    };
    let table = match s {
        Scalar::F32 => [Float32, Float32x2, Float32x3, Float32x4],
        Scalar::U32 => [Uint32, Uint32x2, Uint32x3, Uint32x4],
        Scalar::I32 => [Sint32, Sint32x2, Sint32x3, Sint32x4],
        _ => return None,
    };
    Some(table[usize::from(n) - 1])
}

/// The `#[location]` values of a parameter or result of type `ty` decorated with `io`.
fn locations(m: &Module, ty: &Ty, io: Option<&Io>, out: &mut Vec<rt::Location>) {
    match (io, ty) {
        (Some(Io::Location { location, .. }), t) => {
            if let Some(format) = value_format(t) {
                out.push(rt::Location {
                    location: *location,
                    format,
                });
            }
        }
        (None, &Ty::Struct(id)) => {
            for f in &m.structs[id].fields {
                locations(m, &f.ty, f.io.as_ref(), out);
            }
        }
        _ => {}
    }
}

/// A binding.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BindingInfo {
    /// The `static`'s name.
    pub name: String,
    /// Group.
    pub group: u32,
    /// Binding.
    pub binding: u32,
    /// Stages that use it.
    pub visibility: Visibility,
    /// Kind.
    pub kind: BindingKind,
}

/// Reflection of one variant.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Reflection {
    /// Entry points in declaration order.
    pub entry_points: Vec<EntryPointInfo>,
    /// Bindings sorted by `(group, binding)`.
    pub bindings: Vec<BindingInfo>,
    /// Device features.
    pub features: rt::Features,
}

fn format(wgsl: &str) -> rt::StorageFormat {
    use rt::StorageFormat::*;
    match wgsl {
        "rgba8unorm" => Rgba8Unorm,
        "rgba8snorm" => Rgba8Snorm,
        "rgba8uint" => Rgba8Uint,
        "rgba8sint" => Rgba8Sint,
        "rgba16uint" => Rgba16Uint,
        "rgba16sint" => Rgba16Sint,
        "rgba16float" => Rgba16Float,
        "r32uint" => R32Uint,
        "r32sint" => R32Sint,
        "r32float" => R32Float,
        "rg32uint" => Rg32Uint,
        "rg32sint" => Rg32Sint,
        "rg32float" => Rg32Float,
        "rgba32uint" => Rgba32Uint,
        "rgba32sint" => Rgba32Sint,
        "rgba32float" => Rgba32Float,
        _ => Bgra8Unorm,
    }
}

fn binding_kind(g: &crate::ir::Global, m: &Module, env: &Env) -> BindingKind {
    let dim = |arrayed: bool| {
        if arrayed {
            ViewDimension::D2Array
        } else {
            ViewDimension::D2
        }
    };
    match (&g.ty, g.space) {
        (ty, Space::Uniform) => BindingKind::Uniform {
            min_size: u64::from(layout_of(ty, m, env).size),
        },
        (ty, Space::Storage { read_write }) => BindingKind::Storage {
            read_only: !read_write,
            min_size: u64::from(layout_of(ty, m, env).size),
        },
        (Ty::Texture(t), _) => BindingKind::Texture {
            sample_type: match t.kind {
                TexKind::Depth => SampleType::Depth,
                TexKind::Sampled(Scalar::U32) => SampleType::Uint,
                TexKind::Sampled(Scalar::I32) => SampleType::Sint,
                TexKind::Sampled(_) => SampleType::Float {
                    filterable: !g.unfilterable && !t.multisampled,
                },
            },
            view_dimension: dim(t.arrayed),
            multisampled: t.multisampled,
        },
        (Ty::StorageTexture(f, a), _) => BindingKind::StorageTexture {
            format: format(f.wgsl),
            access: match a {
                Access::Read => StorageAccess::ReadOnly,
                Access::Write => StorageAccess::WriteOnly,
                Access::ReadWrite => StorageAccess::ReadWrite,
            },
            view_dimension: ViewDimension::D2,
        },
        (Ty::Sampler { comparison }, _) => BindingKind::Sampler {
            comparison: *comparison,
        },
        _ => unreachable!("bindings are buffers, textures or samplers"),
    }
}

/// Reflects one variant. `subgroup` and `int64` are the features the pipeline found it needs
/// (declared by `requires(subgroup = ..)`, and 64-bit types in its printed WGSL).
pub fn reflect(m: &Module, env: &Env, subgroup: bool, int64: bool) -> Reflection {
    let mut entry_points = vec![];
    let mut visibility = vec![Visibility::default(); m.globals.len()];
    let mut all_stages = Visibility::default();
    for (i, f) in m.functions.iter().enumerate() {
        let Some(stage) = f.stage.as_ref().filter(|_| entry_present(f, m, env)) else {
            continue;
        };
        let (stage, workgroup_size) = match stage {
            Stage::Compute(size) => {
                let mut ws = [1; 3];
                for (k, e) in size.iter().enumerate() {
                    if let Some(Value::Int(n)) = eval(e, m, env) {
                        ws[k] = n as u32;
                    }
                }
                (rt::Stage::Compute, ws)
            }
            Stage::Vertex => (rt::Stage::Vertex, [0; 3]),
            Stage::Fragment => (rt::Stage::Fragment, [0; 3]),
        };
        let set = |v: &mut Visibility| match stage {
            rt::Stage::Compute => v.compute = true,
            rt::Stage::Vertex => v.vertex = true,
            rt::Stage::Fragment => v.fragment = true,
        };
        set(&mut all_stages);
        let mut workgroup_memory = 0u32;
        for (g, used) in used_globals(m, env, i).into_iter().enumerate() {
            if used {
                set(&mut visibility[g]);
                let global = &m.globals[g];
                if global.space == Space::Workgroup {
                    let size = layout_of(&global.ty, m, env).size;
                    workgroup_memory = workgroup_memory.saturating_add(size.next_multiple_of(16));
                }
            }
        }
        let mut inputs = vec![];
        for p in &f.params {
            locations(m, &f.locals[p.local].ty, p.io.as_ref(), &mut inputs);
        }
        let mut outputs = vec![];
        locations(m, &f.ret, f.ret_io.as_ref(), &mut outputs);
        inputs.sort_by_key(|l| l.location);
        outputs.sort_by_key(|l| l.location);
        entry_points.push(EntryPointInfo {
            name: f.name.clone(),
            stage,
            workgroup_size,
            workgroup_memory,
            inputs,
            outputs,
        });
    }
    let kept = crate::variants::kept_globals(m, env);
    let mut bindings: Vec<BindingInfo> = m
        .globals
        .iter()
        .enumerate()
        .filter(|(i, _)| kept[*i])
        .filter_map(|(i, g)| {
            let (group, binding) = g.binding?;
            let vis = if visibility[i] == Visibility::default() {
                all_stages
            } else {
                visibility[i]
            };
            Some(BindingInfo {
                name: g.name.clone(),
                group,
                binding,
                visibility: vis,
                kind: binding_kind(g, m, env),
            })
        })
        .collect();
    bindings.sort_by_key(|b| (b.group, b.binding));
    Reflection {
        entry_points,
        bindings,
        features: rt::Features { subgroup, int64 },
    }
}
