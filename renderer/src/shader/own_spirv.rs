//! SPIR-V the renderer gives a Vulkan driver itself, where the SPIR-V wgpu writes from a
//! variant's WGSL would be invalid: naga 30 writes a `sample_mask` built-in as a scalar, which
//! Vulkan requires to be an array (VUID-SampleMask-SampleMask-04359; gfx-rs/wgpu#7311).
//!
//! For such a variant (the blended surfaces and particles drawn over the compute rasteriser's
//! samples) the WGSL is written to SPIR-V here with naga, as wgpu would, and the DSL's SPIR-V
//! step (`codegen::spirv_fix::fix_sample_mask`) makes the built-in the array; the module is
//! created with `PASSTHROUGH_SHADERS`, and the program's pipelines take their fragment stage
//! from it ([`super::ShaderProgram::render_pipeline`]). Their vertex stages stay wgpu's.
//!
//! Written from the WGSL, not the variant's build-time SPIR-V: that one is written from the
//! DSL's IR before its axis branches are folded, so it can still name a binding the variant's
//! WGSL left out (a dead branch's texture at a buffer's binding), which the pipeline layout
//! does not have.

use codegen::rt::Variant;

use crate::gpu::adapter::Capabilities;

/// The module of `variant`'s fragment stages (compiled from `source`, its own WGSL), where
/// its SPIR-V has a `SampleMask` built-in: only on Vulkan, on a device with
/// `PASSTHROUGH_SHADERS`, and for the variant's own source (a hot-reloaded replacement
/// compiles from its WGSL as every other variant). `None` otherwise, or where naga refuses the
/// source (the WGSL module then reports it).
pub(super) fn fragment_module(
    device: &wgpu::Device,
    caps: &Capabilities,
    variant: &'static Variant,
    source: &str,
    label: &str,
) -> Option<wgpu::ShaderModule> {
    let wanted = declares_sample_mask(variant.spirv)
        && caps.spirv_passthrough
        && device
            .features()
            .contains(wgpu::Features::PASSTHROUGH_SHADERS)
        && source == variant.wgsl;
    if !wanted {
        return None;
    }
    let words = spirv_of(source, variant.features.subgroup)?;
    let entry_points: Vec<_> = (variant.entry_points.iter())
        .map(|e| wgpu::PassthroughShaderEntryPoint {
            name: e.name.into(),
            workgroup_size: e.workgroup_size.into(),
        })
        .collect();
    // SAFETY: the words are naga's SPIR-V of WGSL naga validated just now (and at build time),
    // with only the `SampleMask` built-in retyped as an array; the DSL's build-time SPIR-V of
    // every variant passes `spirv-val` with that step. Only the fragment stages are used, with
    // the vertex stages wgpu compiles from the same WGSL (so the interfaces match) and the
    // program's explicit layouts from the variant's reflection. Buffer indexing is clamped
    // as wgpu's own checks clamp it (`BoundsCheckPolicy::Restrict`).
    Some(unsafe {
        device.create_shader_module_passthrough(wgpu::ShaderModuleDescriptorPassthrough {
            label: Some(label),
            entry_points: entry_points.into(),
            spirv: Some(words.into()),
            ..Default::default()
        })
    })
}

/// SPIR-V of `source`, with the `SampleMask` built-in an array: in the SPIR-V version the DSL
/// writes the variant in (1.3 with subgroup operations), clip space left to wgpu's viewport.
#[cfg(not(target_arch = "wasm32"))]
pub fn spirv_of(source: &str, subgroup: bool) -> Option<Vec<u32>> {
    use naga::back::spv;
    use naga::proc::{BoundsCheckPolicies, BoundsCheckPolicy};
    let module = naga::front::wgsl::parse_str(source).ok()?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .ok()?;
    let options = spv::Options {
        lang_version: if subgroup { (1, 3) } else { (1, 0) },
        flags: spv::WriterFlags::empty(),
        bounds_check_policies: BoundsCheckPolicies {
            index: BoundsCheckPolicy::Restrict,
            buffer: BoundsCheckPolicy::Restrict,
            image_load: BoundsCheckPolicy::ReadZeroSkipWrite,
            binding_array: BoundsCheckPolicy::Unchecked,
        },
        ..Default::default()
    };
    let words = spv::write_vec(&module, &info, &options, None).ok()?;
    codegen::spirv_fix::fix_sample_mask(&words).ok()
}

/// A browser build has no SPIR-V (and no Vulkan).
#[cfg(target_arch = "wasm32")]
pub fn spirv_of(_source: &str, _subgroup: bool) -> Option<Vec<u32>> {
    None
}

/// Whether SPIR-V `words` decorate a variable `BuiltIn SampleMask` (an entry point uses the
/// built-in; a WGSL struct that declares it but no entry point uses is not there). Empty
/// words (a browser build) have none.
pub fn declares_sample_mask(words: &[u32]) -> bool {
    const DECORATE: u32 = 71;
    const BUILT_IN: u32 = 11;
    const SAMPLE_MASK: u32 = 20;
    let mut at = 5; // after the header
    while let Some(&first) = words.get(at) {
        let (count, opcode) = ((first >> 16) as usize, first & 0xffff);
        if opcode == DECORATE && words.get(at + 2..at + 4) == Some(&[BUILT_IN, SAMPLE_MASK]) {
            return true;
        }
        at += count.max(1);
    }
    false
}
