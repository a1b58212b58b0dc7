//! Materials written in the shader DSL: an engine writes a material as one surface function in
//! its own crate (`#[shader_dsl::material]`), which the material frame wraps into the forward
//! and G-buffer programs of every path, and registers the generated module with the renderer
//! ([`crate::frame::Renderer::register_material`]). A scene's [`crate::scene::Material`] then
//! names it (`custom`, with its parameter record), and its draws are drawn with the program's
//! pipelines. glTF metallic-roughness is the built-in one (`shaders_gen::forward::forward`).
//!
//! ```text
//! // In the engine's shader crate:
//! #[shader_dsl::material(params = Stripes, uses(engine_lib::patterns))]
//! pub mod striped {
//!     pub struct Stripes { pub colour: Vec4, pub frequency: f32, pub pad: Vec3 }
//!     fn surface(point: MaterialPoint, params: Stripes) -> Surface { .. }
//! }
//! // In the engine:
//! renderer.register_material(MaterialProgram::new(&striped::MODULE)?)?;
//! material.custom = Some(CustomShading::new("striped", &striped::Stripes::new(..)));
//! ```
//!
//! On the visibility path each program's kernel (`vis_shade`, the variants of the frame's
//! `msaa` axis above 0) shades the triangles of its own materials over the whole screen; glTF
//! PBR's runs last and writes the image.
//!
//! The depth passes (pre-Z, the shadow casters) draw a custom material's surfaces as glTF's:
//! position, and the alpha mask of the material record (base colour factor × texture × vertex
//! alpha against the cutoff), which the material frame applies to the colour passes too, so
//! depth and colour agree.

use codegen::rt::{Binding, BindingKind, Module, Variant};
use shaders_gen::forward::forward;

/// The entry points every forward variant (`msaa` 0) of a material program has.
const ENTRY_POINTS: [&str; 3] = ["vs_forward", "fs_forward", "fs_gbuffer"];

/// The entry point of every visibility variant (`msaa` above 0) of a material program.
const VIS_ENTRY_POINT: &str = "vis_shade";

/// The sample counts of the visibility path's kernels (the material frame's `msaa` axis above
/// 0).
pub const VIS_SAMPLE_COUNTS: [u32; 4] = [1, 2, 4, 8];

/// The bind group that holds a program's parameter records (`PARAMS`, at [`PARAMS_BINDING`]):
/// the frame's group, which the renderer builds for each program with its own layout.
pub const PARAMS_GROUP: u32 = 0;

/// The binding of a program's parameter records in [`PARAMS_GROUP`].
pub const PARAMS_BINDING: u32 = 19;

/// The name of a program's parameter records in its shaders.
pub const PARAMS_NAME: &str = "PARAMS";

/// Why a module cannot be registered as a material program, or a material cannot use one.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum MaterialError {
    /// The module lacks one of the material frame's variants (list 0 to 2, blend, scalarize
    /// for lists 1 and 2): it was not written with `#[shader_dsl::material]`.
    #[error(
        "module `{module}` has no variant `{variant}`: a material program has every variant of the material frame's axes (list × blend × scalarize); write it with `#[shader_dsl::material]`"
    )]
    MissingVariant {
        /// The material program's module name.
        module: String,
        /// The missing variant: its name (like `list1_blend_scalar`) or its axis values.
        variant: String,
    },
    /// A forward variant lacks `vs_forward`, `fs_forward` or `fs_gbuffer`, or a visibility
    /// variant (`msaa` above 0) `vis_shade`.
    #[error(
        "variant `{module}::{variant}` has no entry point `{entry}`: write the module with `#[shader_dsl::material]`, which adds `vs_forward`, `fs_forward` and `fs_gbuffer`, and `vis_shade` to the visibility kernels"
    )]
    MissingEntryPoint {
        /// The material program's module name.
        module: String,
        /// The variant's name.
        variant: String,
        /// The missing entry point.
        entry: String,
    },
    /// A variant binds something the renderer does not bind: anything glTF PBR's variant of
    /// the same name does not bind identically (the visibility kernels' scene geometry in group
    /// 3 included), except its parameter records, a read-only storage buffer `PARAMS` at group
    /// 0, binding 19.
    #[error(
        "variant `{module}::{variant}` binds `{binding}` at group {group}, binding {number}, which the renderer does not provide there: groups 0 to 2 are the material frame's (the frame, the draw records, the material table), and a material's own resources are its `params` records at group 0, binding 19"
    )]
    ForeignBinding {
        /// The material program's module name.
        module: String,
        /// The variant's name.
        variant: String,
        /// The binding's name in the shader.
        binding: String,
        /// Its bind group index.
        group: u32,
        /// Its binding index within the group.
        number: u32,
    },
    /// A variant binds fewer entries of group 1 or 2 than glTF PBR's program, so the scene's
    /// bind group would not fit its layout.
    #[error(
        "variant `{module}::{variant}` does not bind all of group {group}, which the renderer binds with the scene's own bind group: a material must read the material frame's draw records and material table as the frame does"
    )]
    SceneGroup {
        /// The material program's module name.
        module: String,
        /// The variant's name.
        variant: String,
        /// The incomplete group (1 or 2).
        group: u32,
    },
    /// [`MaterialProgram::new`] was given the built-in glTF module (`shaders_gen::forward`).
    #[error("module `{0}` is glTF PBR's own program, which every renderer has")]
    BuiltIn(String),
    /// A material's `custom` names a program the renderer has not registered (checked when a
    /// scene or material is uploaded, and when programs are registered).
    #[error(
        "material `{material}` names material program `{program}`, which this renderer has not registered; call `Renderer::register_material` with it first"
    )]
    Unregistered {
        /// The material's name.
        material: String,
        /// The program it names.
        program: String,
    },
    /// A material's parameter record is not the size of its program's parameter struct.
    #[error(
        "material `{material}` gives {given} bytes of parameters to material program `{program}`, whose parameter struct has {expected} (pass its generated host struct to `CustomShading::new`)"
    )]
    ParamsSize {
        /// The material's name.
        material: String,
        /// The program it names.
        program: String,
        /// Bytes of the material's record.
        given: usize,
        /// Bytes of the program's parameter struct.
        expected: u64,
    },
    /// A material with a program has [`AlphaMode::Blend`](crate::scene::AlphaMode::Blend);
    /// use opaque or masked, or glTF PBR for blended surfaces.
    #[error(
        "material `{material}` is alpha-blended with material program `{program}`: blended surfaces are drawn back to front in one draw through glTF PBR's pipeline, so a material program shades opaque and masked materials only"
    )]
    Blended {
        /// The material's name.
        material: String,
        /// The program it names.
        program: String,
    },
}

/// Checks that `material`'s program (if any) is one of `programs`, with a parameter record of
/// its size, and that the material is not blended.
pub(crate) fn check_material(
    material: &crate::scene::Material,
    programs: &[MaterialProgram],
) -> Result<(), MaterialError> {
    let Some(custom) = &material.custom else {
        return Ok(());
    };
    let program = programs
        .iter()
        .find(|p| p.name() == custom.program)
        .ok_or_else(|| MaterialError::Unregistered {
            material: material.name.clone(),
            program: custom.program.clone(),
        })?;
    if custom.params.len() as u64 != program.params_size() {
        return Err(MaterialError::ParamsSize {
            material: material.name.clone(),
            program: custom.program.clone(),
            given: custom.params.len(),
            expected: program.params_size(),
        });
    }
    if material.alpha_mode == crate::scene::AlphaMode::Blend {
        return Err(MaterialError::Blended {
            material: material.name.clone(),
            program: custom.program.clone(),
        });
    }
    Ok(())
}

/// A material written in the DSL, ready to register: its generated module, checked to be a
/// material frame's programs whose bindings the renderer provides.
#[derive(Debug, Clone, Copy)]
pub struct MaterialProgram {
    module: &'static Module,
    /// Bytes of one parameter record (0: the program takes none).
    params_size: u64,
}

impl MaterialProgram {
    /// The program of a module written with `#[shader_dsl::material]` (its generated
    /// `MODULE`), checked: every variant of the frame's axes, each with the frame's entry
    /// points, binding only what the glTF program's variant of the same name binds, and its
    /// parameter records.
    pub fn new(module: &'static Module) -> Result<Self, MaterialError> {
        if module.name == forward::MODULE.name {
            return Err(MaterialError::BuiltIn(module.name.to_string()));
        }
        let mut params_size = 0;
        for (name, entries) in variant_names() {
            let missing = || MaterialError::MissingVariant {
                module: module.name.to_string(),
                variant: name.clone(),
            };
            let variant = module.variant_named(&name).ok_or_else(missing)?;
            let reference = forward::MODULE.variant_named(&name).ok_or_else(missing)?;
            check_entry_points(variant, entries)?;
            check_scene_groups(variant, reference)?;
            for binding in variant.bindings {
                params_size = params_size.max(check_binding(variant, reference, binding)?);
            }
        }
        Ok(Self {
            module,
            params_size,
        })
    }

    /// The module's name: what a material's `CustomShading::program` names.
    pub fn name(&self) -> &'static str {
        self.module.name
    }

    /// Bytes of one parameter record (its host struct's size), 0 for a program without one.
    pub fn params_size(&self) -> u64 {
        self.params_size
    }

    /// The variant of a path's list kind (0 naive, 1 tiled, 2 clustered), `blend` and
    /// `scalarize` (which the naive list does not have).
    pub(crate) fn variant(
        &self,
        list: u32,
        blend: bool,
        scalarize: bool,
    ) -> Option<&'static Variant> {
        self.module
            .variant_named(&variant_name(list, blend, scalarize && list > 0))
    }

    /// The visibility kernel of `msaa` samples ([`VIS_SAMPLE_COUNTS`]), plain or scalarized.
    pub(crate) fn vis_variant(
        &self,
        msaa: u32,
        scalarize: bool,
        vis64: bool,
    ) -> Option<&'static Variant> {
        self.module
            .variant_named(&vis_variant_name(msaa, scalarize, vis64))
    }
}

/// The name of the visibility kernel's variant of `msaa` samples: clustered lists, opaque
/// (`list2`, `scalar`, then `msaa`, then `vis64` where it reads the compute rasteriser's
/// buffer).
pub(crate) fn vis_variant_name(msaa: u32, scalarize: bool, vis64: bool) -> String {
    let buffer = if vis64 { "_vis64" } else { "" };
    format!("{}_msaa{msaa}{buffer}", variant_name(2, false, scalarize))
}

/// The name of the frame's variant of `list`, `blend` and `scalarize`, as the DSL names keys
/// (axis labels `list`, `blend`, `scalar`).
fn variant_name(list: u32, blend: bool, scalarize: bool) -> String {
    let mut name = format!("list{list}");
    if blend {
        name.push_str("_blend");
    }
    if scalarize {
        name.push_str("_scalar");
    }
    name
}

/// Every variant name of the frame's axes, with the entry points the variant has: the forward
/// ones, then the visibility kernels.
fn variant_names() -> impl Iterator<Item = (String, &'static [&'static str])> {
    (0..3u32)
        .flat_map(|list| {
            [(false, false), (true, false), (false, true), (true, true)]
                .into_iter()
                .filter(move |&(_, scalarize)| list > 0 || !scalarize)
                .map(move |(blend, scalarize)| {
                    (variant_name(list, blend, scalarize), &ENTRY_POINTS[..])
                })
        })
        .chain(VIS_SAMPLE_COUNTS.into_iter().flat_map(|msaa| {
            [(false, false), (true, false), (false, true), (true, true)]
                .into_iter()
                .map(move |(scalarize, vis64)| {
                    let name = vis_variant_name(msaa, scalarize, vis64);
                    (name, &[VIS_ENTRY_POINT][..])
                })
        }))
}

/// Groups 1 (draw records) and 2 (material table) are bound with the scene's bind groups,
/// made against the glTF program's layouts: a material's must be the very same.
fn check_scene_groups(variant: &Variant, reference: &Variant) -> Result<(), MaterialError> {
    for group in [1, 2] {
        let theirs: Vec<&Binding> = reference.group(group).collect();
        for (i, binding) in variant.group(group).enumerate() {
            if theirs.get(i) != Some(&binding) {
                return Err(MaterialError::ForeignBinding {
                    module: variant.module.to_string(),
                    variant: variant.name().to_string(),
                    binding: binding.name.to_string(),
                    group,
                    number: binding.binding,
                });
            }
        }
        if variant.group(group).count() != theirs.len() {
            return Err(MaterialError::SceneGroup {
                module: variant.module.to_string(),
                variant: variant.name().to_string(),
                group,
            });
        }
    }
    Ok(())
}

fn check_entry_points(variant: &Variant, entries: &[&str]) -> Result<(), MaterialError> {
    for &entry in entries {
        if variant.entry_point(entry).is_none() {
            return Err(MaterialError::MissingEntryPoint {
                module: variant.module.to_string(),
                variant: variant.name().to_string(),
                entry: entry.to_string(),
            });
        }
    }
    Ok(())
}

/// Checks one binding of a material variant: its parameter records (whose record size it
/// returns), or one the glTF variant `reference` has, the same.
fn check_binding(
    variant: &Variant,
    reference: &Variant,
    binding: &Binding,
) -> Result<u64, MaterialError> {
    let foreign = || MaterialError::ForeignBinding {
        module: variant.module.to_string(),
        variant: variant.name().to_string(),
        binding: binding.name.to_string(),
        group: binding.group,
        number: binding.binding,
    };
    if binding.group == PARAMS_GROUP && binding.name == PARAMS_NAME {
        return match binding.kind {
            BindingKind::Storage {
                read_only: true,
                min_size,
            } if binding.binding == PARAMS_BINDING => Ok(min_size),
            _ => Err(foreign()),
        };
    }
    // Anything else (the visibility kernels' scene geometry in group 3 too) as glTF's has it.
    let same = reference.bindings.iter().any(|r| {
        (r.name, r.group, r.binding, r.kind)
            == (binding.name, binding.group, binding.binding, binding.kind)
    });
    if same { Ok(0) } else { Err(foreign()) }
}
