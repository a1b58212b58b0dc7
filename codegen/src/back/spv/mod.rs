//! SPIR-V through naga's SPIR-V backend. SPIR-V 1.3 when the variant uses subgroup
//! operations (`spirv-val` rejects them in 1.0), otherwise 1.0. No debug info, so the output
//! does not depend on the build profile.
//!
//! naga 30's output goes through [`fix_sample_mask`] (`crate::spirv_fix`), which makes the
//! `SampleMask` built-in the array Vulkan requires, so every variant passes `spirv-val`.
//!
//! Must only be given modules that passed [`crate::validate`]; it never validates itself.

pub use crate::spirv_fix::fix_sample_mask;

use crate::validate::Validated;

/// The SPIR-V version a variant is written in.
pub fn version(subgroup: bool) -> (u8, u8) {
    if subgroup { (1, 3) } else { (1, 0) }
}

/// Writes all entry points of a validated module as one SPIR-V module.
pub fn write_vec(v: &Validated, subgroup: bool) -> Result<Vec<u32>, String> {
    let options = naga::back::spv::Options {
        lang_version: version(subgroup),
        flags: naga::back::spv::WriterFlags::ADJUST_COORDINATE_SPACE
            | naga::back::spv::WriterFlags::LABEL_VARYINGS
            | naga::back::spv::WriterFlags::CLAMP_FRAG_DEPTH,
        fake_missing_bindings: true,
        ..Default::default()
    };
    let words = naga::back::spv::write_vec(&v.module, &v.info, &options, None)
        .map_err(|e| e.to_string())?;
    fix_sample_mask(&words).map_err(|e| format!("rewriting naga's SPIR-V: {e}"))
}
