//! The SPIR-V the renderer gives a Vulkan driver itself for the variants with a `sample_mask`
//! built-in (`renderer/src/shader/own_spirv.rs`): which variants, and that `spirv-val` accepts
//! it where it refuses naga 30's own.
use renderer::shader::{declares_sample_mask, spirv_of};
use shaders_gen::forward::forward;
use shaders_gen::particles::particle_draw;

/// `spirv-val`'s verdict on `words` for Vulkan 1.1 (SPIR-V up to 1.3); an error also where
/// it cannot run (`cargo xtask test` installs it).
fn spirv_val(words: &[u32], name: &str) -> Result<(), String> {
    let path = std::env::temp_dir().join(format!("own-spirv-{}-{name}.spv", std::process::id()));
    std::fs::write(&path, bytemuck::cast_slice::<u32, u8>(words)).map_err(|e| e.to_string())?;
    let out = std::process::Command::new("spirv-val")
        .args(["--target-env", "vulkan1.1"])
        .arg(&path)
        .output()
        .map_err(|e| format!("spirv-val does not run: {e}"));
    let _ = std::fs::remove_file(&path);
    let out = out?;
    if out.status.success() {
        Ok(())
    } else {
        Err(String::from_utf8_lossy(&out.stderr).into_owned())
    }
}

/// The variants whose fragment stages go to the driver as SPIR-V of the renderer's own are
/// exactly the blended ones over the compute rasteriser's samples (`fs_forward_vis64`, at
/// each sample count, plain and scalarized), and what it writes for them passes
/// `spirv-val`, where naga's own SPIR-V of the same WGSL does not (the scalar
/// `SampleMask`).
#[test]
fn the_sample_mask_variants_get_valid_spirv() {
    let own: Vec<_> = (forward::VARIANTS.iter().chain(particle_draw::VARIANTS))
        .filter(|v| declares_sample_mask(v.spirv))
        .collect();
    let names: Vec<_> = own.iter().map(|v| v.name()).collect();
    assert_eq!(own.len(), 8, "{names:?}");
    assert!(
        names
            .iter()
            .all(|n| n.contains("_blend") && n.ends_with("_vis64")),
        "{names:?}"
    );
    for v in own {
        let words = spirv_of(v.wgsl, v.features.subgroup).expect("naga writes it");
        if let Err(e) = spirv_val(&words, v.name()) {
            panic!("{}: {e}", v.name());
        }
    }
    // What wgpu would give the driver: naga's SPIR-V of the same source, unrewritten.
    let v = forward::variant(forward::VariantKey {
        list: forward::List::List2,
        blend: true,
        scalarize: false,
        msaa: forward::Msaa::Msaa4,
        vis64: true,
    })
    .expect("variant");
    let module = naga::front::wgsl::parse_str(v.wgsl).expect("parses");
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .expect("validates");
    let options = naga::back::spv::Options::default();
    let naga_words = naga::back::spv::write_vec(&module, &info, &options, None).expect("spv");
    let refused = spirv_val(&naga_words, "naga").expect_err("naga 30's SampleMask is a scalar");
    assert!(refused.contains("SampleMask"), "{refused}");
}
