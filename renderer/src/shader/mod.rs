//! Turns the DSL's generated shader variants into wgpu objects.
//!
//! `shaders_gen` exposes each variant as plain data ([`codegen::rt::Variant`]): WGSL, entry
//! points, bindings and required features. This module is the only place that maps that data to
//! wgpu (with `shader_bind`, which turns reflected bindings into layout entries and builds bind
//! groups by binding name), so no pass writes a bind-group layout by hand. It holds no shader source of its own;
//! `hot` holds replacements of generated WGSL installed while the program runs (hot reload).

mod binding_log;
pub mod hot;
#[cfg(test)]
mod layout_tests;
mod pipeline_memo;
pub(crate) mod store;
#[cfg(test)]
mod test_variant;

pub use shader_bind::{bind_group_layout_entries, storage_format};

use codegen::rt::{Stage, Variant};

use crate::gpu::adapter::Capabilities;
use binding_log::BindingLog;
use pipeline_memo::PipelineMemo;

/// Why a generated variant cannot be used on this device.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
#[non_exhaustive]
pub enum VariantError {
    /// A scalarized variant (subgroup operations) on a device without subgroup support.
    #[error(
        "shader variant `{module}::{variant}` needs the SUBGROUP feature, which this device lacks; \
         use a non-scalarized variant (scalarize off) or an adapter with subgroup support"
    )]
    MissingSubgroup {
        /// The DSL module of the variant.
        module: &'static str,
        /// The variant's stable name.
        variant: &'static str,
    },
    /// A variant that uses `u64` (the `Atomic<u64>` `fetch_min`/`fetch_max` of the compute
    /// rasteriser) on a device without 64-bit integer atomics
    /// ([`Capabilities::int64_atomic_min_max`]).
    #[error(
        "shader variant `{module}::{variant}` uses 64-bit integers and needs the SHADER_INT64 and \
         SHADER_INT64_ATOMIC_MIN_MAX features, which this device lacks; use a path without them \
         or an adapter that has both"
    )]
    MissingInt64 {
        /// The DSL module of the variant.
        module: &'static str,
        /// The variant's stable name.
        variant: &'static str,
    },
    /// [`ShaderProgram::entry`] (or a pipeline builder) asked for an entry point the variant
    /// lacks at that stage.
    #[error("shader variant `{module}::{variant}` has no {stage:?} entry point named `{entry}`")]
    NoEntryPoint {
        /// The DSL module of the variant.
        module: &'static str,
        /// The variant's stable name.
        variant: &'static str,
        /// The stage asked for.
        stage: Stage,
        /// The entry point name asked for.
        entry: String,
    },
    /// An entry point's workgroup has more invocations than the device's
    /// `max_workgroup_invocations`.
    #[error(
        "shader variant `{module}::{variant}` needs a {invocations}-invocation workgroup, but the \
         device allows {allowed}; choose a smaller tile size"
    )]
    WorkgroupTooLarge {
        /// The DSL module of the variant.
        module: &'static str,
        /// The variant's stable name.
        variant: &'static str,
        /// The largest workgroup among its entry points (x * y * z).
        invocations: u32,
        /// The device's limit ([`Capabilities::max_workgroup_invocations`]).
        allowed: u32,
    },
}

/// Checks that `variant` can run on a device with `caps`, before any wgpu call could fail.
pub fn check_supported(variant: &Variant, caps: &Capabilities) -> Result<(), VariantError> {
    if variant.features.subgroup && caps.subgroup.is_none() {
        return Err(VariantError::MissingSubgroup {
            module: variant.module,
            variant: variant.name(),
        });
    }
    if variant.features.int64 && !caps.int64_atomic_min_max {
        return Err(VariantError::MissingInt64 {
            module: variant.module,
            variant: variant.name(),
        });
    }
    if let Some(invocations) = variant
        .entry_points
        .iter()
        .map(|e| e.workgroup_size.iter().product::<u32>())
        .max()
        .filter(|&n| n > caps.max_workgroup_invocations)
    {
        return Err(VariantError::WorkgroupTooLarge {
            module: variant.module,
            variant: variant.name(),
            invocations,
            allowed: caps.max_workgroup_invocations,
        });
    }
    Ok(())
}

/// The WGSL to compile for `variant` on a device with `caps`: the generated source or its
/// hot-reloaded replacement, after the `enable` directives a browser needs.
pub(crate) fn source_for(
    variant: &'static Variant,
    caps: &Capabilities,
) -> std::borrow::Cow<'static, str> {
    let source = hot::wgsl_of(variant);
    let directives = codegen::web::browser_directives(variant);
    if caps.browser && !directives.is_empty() {
        std::borrow::Cow::Owned(format!("{directives}{source}"))
    } else {
        source
    }
}

/// A variant compiled on a device: its shader module and bind-group layouts.
#[derive(Debug, Clone)]
pub struct ShaderProgram {
    /// The generated variant it was compiled from.
    pub variant: &'static Variant,
    /// The compiled WGSL (the generated source, or its hot-reloaded replacement).
    pub module: wgpu::ShaderModule,
    /// On Vulkan, for a variant with a `sample_mask` built-in: the variant's own build-time
    /// SPIR-V, given to the driver as it is ([`shader_bind::driver_module`]), which
    /// [`ShaderProgram::render_pipeline`] uses for the fragment stage of the pipelines built
    /// from `module`. wgpu's SPIR-V of the WGSL would declare that built-in as a scalar, which
    /// Vulkan refuses (naga 30; gfx-rs/wgpu#7311).
    fragment_spirv: Option<wgpu::ShaderModule>,
    /// One layout per group index `0..variant.group_count()` (empty where a group is unused).
    pub bind_group_layouts: Vec<wgpu::BindGroupLayout>,
    /// All of `bind_group_layouts` in group order, no immediates.
    pub pipeline_layout: wgpu::PipelineLayout,
    /// What its bind groups held, where asked (`record_bindings`).
    binding_log: BindingLog,
    /// The pipelines built from it, shared by every copy of this compilation.
    pipelines: std::sync::Arc<PipelineMemo>,
}

impl ShaderProgram {
    /// Whether the fragment stages of this program's pipelines take the variant's build-time
    /// SPIR-V rather than wgpu's (a `sample_mask` built-in on Vulkan).
    pub fn has_own_fragment_spirv(&self) -> bool {
        self.fragment_spirv.is_some()
    }

    /// The layout of bind group `group` (below `variant.group_count()`; empty where the
    /// variant binds nothing in it).
    pub fn layout(&self, group: u32) -> &wgpu::BindGroupLayout {
        &self.bind_group_layouts[group as usize]
    }

    /// Compiles `variant` on `device` after checking it against `caps`: a program of its own.
    /// Renderers take theirs from [`crate::GpuContext::program`], which compiles each variant
    /// once per device.
    pub fn new(
        device: &wgpu::Device,
        caps: &Capabilities,
        variant: &'static Variant,
    ) -> Result<Self, VariantError> {
        check_supported(variant, caps)?;
        Ok(Self::compile(
            device,
            caps,
            variant,
            source_for(variant, caps),
        ))
    }

    /// Compiles `source` (the WGSL of `variant`, or its hot-reloaded replacement), and for its
    /// fragment stages the variant's build-time SPIR-V where wgpu's would be invalid: on
    /// Vulkan with `PASSTHROUGH_SHADERS`, for the variant's own source (a hot-reloaded
    /// replacement compiles from its WGSL as every other variant).
    fn compile(
        device: &wgpu::Device,
        caps: &Capabilities,
        variant: &'static Variant,
        source: std::borrow::Cow<'static, str>,
    ) -> Self {
        let label = format!("{}::{}", variant.module, variant.name());
        let fragment_spirv =
            (variant.uses_sample_mask() && caps.spirv_passthrough && source == variant.wgsl)
                .then(|| shader_bind::driver_module(device, variant, &label))
                .flatten();
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(&label),
            source: wgpu::ShaderSource::Wgsl(source),
        });
        let bind_group_layouts: Vec<_> = (0..variant.group_count())
            .map(|group| {
                device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some(&format!("{label} group {group}")),
                    entries: &bind_group_layout_entries(variant, group),
                })
            })
            .collect();
        let layout_refs: Vec<Option<&wgpu::BindGroupLayout>> =
            bind_group_layouts.iter().map(Some).collect();
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(&label),
            bind_group_layouts: &layout_refs,
            immediate_size: 0,
        });
        Self {
            variant,
            module,
            fragment_spirv,
            bind_group_layouts,
            pipeline_layout,
            binding_log: BindingLog::default(),
            pipelines: std::sync::Arc::default(),
        }
    }

    /// The same compilation and pipeline memo with a binding log of its own.
    fn fresh_copy(&self) -> Self {
        Self {
            binding_log: BindingLog::default(),
            ..self.clone()
        }
    }

    /// Bind group `group` of this program from `resources` (numbered from the variant's
    /// reflection and checked against it, as [`shader_bind::Resources::build`] does).
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        group: u32,
        resources: &shader_bind::Resources<'_>,
        label: &str,
    ) -> Result<wgpu::BindGroup, shader_bind::BindError> {
        let built = resources.build(device, self.layout(group), self.variant, group, label)?;
        self.binding_log.note(self.variant, group, resources);
        Ok(built)
    }

    /// From now on, keeps what each bind group built through [`ShaderProgram::bind_group`]
    /// held (its last build), for [`ShaderProgram::bound`]. Clones of the program share it.
    #[cfg(any(test, feature = "internals"))]
    #[doc(hidden)]
    pub fn record_bindings(&self) {
        self.binding_log.start();
    }

    /// The resources kept since [`ShaderProgram::record_bindings`]: group, binding name and
    /// resource, in group order.
    #[cfg(any(test, feature = "internals"))]
    #[doc(hidden)]
    pub fn bound(&self) -> Vec<(u32, &'static str, shader_bind::BoundResource)> {
        self.binding_log.bound()
    }

    /// The name of the entry point of `stage` called `name`, checked to exist.
    pub fn entry(&self, stage: Stage, name: &str) -> Result<&'static str, VariantError> {
        self.variant
            .entry_points
            .iter()
            .find(|e| e.stage == stage && e.name == name)
            .map(|e| e.name)
            .ok_or_else(|| VariantError::NoEntryPoint {
                module: self.variant.module,
                variant: self.variant.name(),
                stage,
                entry: name.to_owned(),
            })
    }

    /// A compute pipeline for the compute entry point `name`.
    pub fn compute_pipeline(
        &self,
        device: &wgpu::Device,
        name: &str,
    ) -> Result<wgpu::ComputePipeline, VariantError> {
        let entry = self.entry(Stage::Compute, name)?;
        Ok(self.pipelines.compute(entry, || {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&self.pipeline_layout),
                module: &self.module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        }))
    }

    /// The render pipeline `desc` describes, built once per compilation of this program when
    /// `desc` uses its module and layout (the key is the rest of the descriptor); built anew
    /// otherwise.
    pub fn render_pipeline(
        &self,
        device: &wgpu::Device,
        desc: &wgpu::RenderPipelineDescriptor<'_>,
    ) -> wgpu::RenderPipeline {
        let own = desc.layout == Some(&self.pipeline_layout)
            && desc.vertex.module == &self.module
            && desc
                .fragment
                .as_ref()
                .is_none_or(|f| f.module == &self.module)
            && desc.cache.is_none();
        if !own {
            return device.create_render_pipeline(desc);
        }
        self.pipelines.render(pipeline_memo::render_key(desc), || {
            match (&self.fragment_spirv, &desc.fragment) {
                (Some(module), Some(fragment)) => {
                    let fragment = wgpu::FragmentState {
                        module,
                        ..fragment.clone()
                    };
                    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                        fragment: Some(fragment),
                        ..desc.clone()
                    })
                }
                _ => device.create_render_pipeline(desc),
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::test_variant::{INT64_VARIANT, VARIANT};
    use super::*;

    fn caps() -> Capabilities {
        Capabilities {
            subgroup: None,
            timestamp_query: false,
            timestamp_inside_passes: false,
            msaa_depth32float: vec![1, 4],
            msaa_rgba16float: vec![1, 4],
            msaa_r32uint: vec![1],
            max_workgroup_invocations: 1024,
            int64_atomic_min_max: false,
            spirv_passthrough: false,
            browser: false,
        }
    }

    #[test]
    fn subgroup_variant_is_refused_without_subgroup() {
        let mut caps = caps();
        let err = check_supported(&VARIANT, &caps).unwrap_err();
        assert!(
            err.to_string().contains("needs the SUBGROUP feature"),
            "{err}"
        );
        caps.subgroup = Some(crate::gpu::adapter::SubgroupSize { min: 8, max: 8 });
        assert_eq!(check_supported(&VARIANT, &caps), Ok(()));
        caps.max_workgroup_invocations = 128;
        assert!(matches!(
            check_supported(&VARIANT, &caps),
            Err(VariantError::WorkgroupTooLarge {
                invocations: 256,
                ..
            })
        ));
    }

    #[test]
    fn a_browser_gets_the_enable_directives_its_variant_needs() {
        let mut caps = caps();
        assert_eq!(source_for(&VARIANT, &caps), VARIANT.wgsl);
        caps.browser = true;
        let source = source_for(&VARIANT, &caps);
        assert!(source.starts_with("enable subgroups;"), "{source}");
        assert!(source.ends_with(VARIANT.wgsl));
        // A variant without subgroup operations needs no directive.
        assert_eq!(source_for(&INT64_VARIANT, &caps), INT64_VARIANT.wgsl);
    }

    #[test]
    fn int64_variant_is_refused_without_int64_atomics() {
        let mut caps = caps();
        let err = check_supported(&INT64_VARIANT, &caps).unwrap_err();
        assert_eq!(
            err,
            VariantError::MissingInt64 {
                module: "raster",
                variant: "t16",
            }
        );
        let msg = err.to_string();
        for part in [
            "raster::t16",
            "SHADER_INT64 and SHADER_INT64_ATOMIC_MIN_MAX",
        ] {
            assert!(msg.contains(part), "{msg}");
        }
        // A variant without 64-bit integers does not need them.
        caps.subgroup = Some(crate::gpu::adapter::SubgroupSize { min: 8, max: 8 });
        assert_eq!(check_supported(&VARIANT, &caps), Ok(()));
        caps.int64_atomic_min_max = true;
        assert_eq!(check_supported(&INT64_VARIANT, &caps), Ok(()));
    }
}
