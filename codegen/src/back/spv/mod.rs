//! SPIR-V through naga's SPIR-V backend. SPIR-V 1.3 when the variant uses subgroup
//! operations (`spirv-val` rejects them in 1.0), otherwise 1.0. No debug info, so the output
//! does not depend on the build profile.
//!
//! naga 30's output goes through [`fix_sample_mask`] (`crate::spirv_fix`), which makes the
//! `SampleMask` built-in the array Vulkan requires, so every variant passes `spirv-val`.
//!
//! Indexing is bounds-checked as wgpu checks it ([`BOUNDS_CHECKS`]).
//!
//! Must only be given modules that passed [`crate::validate`]; it never validates itself.

pub use crate::spirv_fix::fix_sample_mask;

use crate::validate::Validated;

/// The SPIR-V version a variant is written in.
pub fn version(subgroup: bool) -> (u8, u8) {
    if subgroup { (1, 3) } else { (1, 0) }
}

/// How the SPIR-V guards indexing: as wgpu 30's Vulkan backend guards the SPIR-V it writes on a
/// device without robust buffer and image access (indices, buffer accesses and image loads
/// clamped into range; binding arrays, which wgpu leaves unchecked, too), so a driver may be
/// given these words as they are (`shader_bind::driver_module`) with the guarantees wgpu's own
/// SPIR-V has.
pub const BOUNDS_CHECKS: naga::proc::BoundsCheckPolicies = naga::proc::BoundsCheckPolicies {
    index: naga::proc::BoundsCheckPolicy::Restrict,
    buffer: naga::proc::BoundsCheckPolicy::Restrict,
    image_load: naga::proc::BoundsCheckPolicy::Restrict,
    binding_array: naga::proc::BoundsCheckPolicy::Unchecked,
};

/// Writes all entry points of a validated module as one SPIR-V module.
pub fn write_vec(v: &Validated, subgroup: bool) -> Result<Vec<u32>, String> {
    let options = naga::back::spv::Options {
        lang_version: version(subgroup),
        flags: naga::back::spv::WriterFlags::ADJUST_COORDINATE_SPACE
            | naga::back::spv::WriterFlags::LABEL_VARYINGS
            | naga::back::spv::WriterFlags::CLAMP_FRAG_DEPTH,
        fake_missing_bindings: true,
        bounds_check_policies: BOUNDS_CHECKS,
        ..Default::default()
    };
    let words = naga::back::spv::write_vec(&v.module, &v.info, &options, None)
        .map_err(|e| e.to_string())?;
    fix_sample_mask(&words).map_err(|e| format!("rewriting naga's SPIR-V: {e}"))
}
