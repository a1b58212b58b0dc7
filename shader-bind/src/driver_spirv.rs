//! A variant's own SPIR-V given to a Vulkan driver as it is, for the variants whose SPIR-V
//! wgpu would write invalidly: naga 30 declares the `sample_mask` built-in as a scalar, which
//! Vulkan requires to be an array (VUID-SampleMask-SampleMask-04359; gfx-rs/wgpu#7311).
//!
//! The DSL writes every variant's SPIR-V at build time from the same validated WGSL it prints
//! (`codegen::back::spv`): `SampleMask` as the array, indexing bounds-checked as wgpu's Vulkan
//! backend checks it without robust access, and `spirv-val` accepts every variant (the DSL's
//! golden tests and `shaders_gen`'s). Only a generated [`Variant`]'s words can be given here,
//! never words written by hand.

use codegen::rt::Variant;

/// A shader module of `variant`'s build-time SPIR-V ([`Variant::spirv`]), created with
/// `PASSTHROUGH_SHADERS`: `None` where the device lacks that feature, or in a build without
/// SPIR-V (a browser build's variants have no words).
///
/// Its vertex entry points write clip-space `y` flipped (the DSL writes SPIR-V for Vulkan's
/// viewport; wgpu flips the viewport instead), so a pipeline takes only its fragment or
/// compute stage from it, and its vertex stage from the variant's WGSL module.
pub fn driver_module(
    device: &wgpu::Device,
    variant: &'static Variant,
    label: &str,
) -> Option<wgpu::ShaderModule> {
    let usable = !variant.spirv.is_empty()
        && device
            .features()
            .contains(wgpu::Features::PASSTHROUGH_SHADERS);
    if !usable {
        return None;
    }
    let entry_points: Vec<_> = (variant.entry_points.iter())
        .map(|e| wgpu::PassthroughShaderEntryPoint {
            name: e.name.into(),
            workgroup_size: e.workgroup_size.into(),
        })
        .collect();
    // SAFETY: the words are the DSL's build-time SPIR-V of WGSL naga validated, written with
    // the bounds checks wgpu's Vulkan backend inserts ([`codegen::rt::Variant::spirv`]), and
    // `spirv-val` accepts every generated variant. The caller binds the layouts reflected
    // from the same variant, so every resource the words declare is in them.
    Some(unsafe {
        device.create_shader_module_passthrough(wgpu::ShaderModuleDescriptorPassthrough {
            label: Some(label),
            entry_points: entry_points.into(),
            spirv: Some(variant.spirv.into()),
            ..Default::default()
        })
    })
}
