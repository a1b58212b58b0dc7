//! The build-time SPIR-V of `shaders_gen`'s variants: every one passes `spirv-val`, and the
//! variants that use the `sample_mask` built-in, whose fragment stages a Vulkan driver is given
//! as these words (`shader_bind::driver_module`), are exactly the blended and the alpha-masked
//! ones over the compute rasteriser's samples.
use shaders_gen::forward::forward;
use shaders_gen::particles::particle_draw;
use shaders_gen::visibility::vis_raster;

/// `spirv-val`'s verdict on `words` for Vulkan 1.1 (SPIR-V up to 1.3); an error also where
/// it cannot run (`cargo xtask test` installs it).
fn spirv_val(words: &[u32], name: &str) -> Result<(), String> {
    let path = std::env::temp_dir().join(format!("driver-spirv-{}-{name}.spv", std::process::id()));
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

/// Every variant of every module: its SPIR-V is what a driver may be given as it is.
#[test]
fn every_shaders_gen_variant_passes_spirv_val() {
    let mut refused = vec![];
    let mut checked = 0;
    for module in shaders_gen::MODULES {
        for v in module.variants {
            let name = format!("{}-{}", module.name, v.name());
            if let Err(e) = spirv_val(v.spirv, &name) {
                refused.push(format!("{name}: {e}"));
            }
            checked += 1;
        }
    }
    assert!(checked > 100, "{checked} variants");
    assert!(refused.is_empty(), "{}", refused.join("\n"));
}

/// The variants that use `sample_mask` are exactly the blended ones over the compute
/// rasteriser's samples (`fs_forward_vis64`, at each sample count, plain and scalarized) and the
/// alpha-masked draws that merge into them (`fs_vis64`, at each sample count), and their SPIR-V
/// declares it as an array, where naga's own SPIR-V of the same WGSL, which wgpu would give the
/// driver, declares a scalar that `spirv-val` refuses.
#[test]
fn only_the_variants_over_the_compute_rasterisers_samples_use_the_sample_mask() {
    let users: Vec<_> = (forward::VARIANTS.iter().chain(particle_draw::VARIANTS))
        .chain(vis_raster::VARIANTS)
        .filter(|v| v.uses_sample_mask())
        .collect();
    let names: Vec<_> = users.iter().map(|v| v.name()).collect();
    assert_eq!(users.len(), 12, "{names:?}");
    let blended = |n: &str| n.contains("_blend") && n.ends_with("_vis64");
    let masked = |n: &str| n.starts_with("mask_vis64_msaa");
    assert!(
        names.iter().filter(|n| blended(n)).count() == 8
            && names.iter().filter(|n| masked(n)).count() == 4,
        "{names:?}"
    );
    let v = forward::variant(forward::VariantKey {
        list: forward::List::List2,
        blend: true,
        scalarize: false,
        msaa: forward::Msaa::Msaa4,
        vis64: true,
    })
    .expect("variant");
    spirv_val(v.spirv, "own").expect("the variant's SPIR-V");
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
