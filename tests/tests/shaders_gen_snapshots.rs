//! Snapshots of the WGSL of every variant of every `shaders_gen` module, so a change to a kernel
//! or to the generator shows up as a reviewable diff (`tests/tests/snapshots/`).
//!
//! To re-approve after a deliberate change: `INSTA_UPDATE=always cargo test -p tests --test
//! shaders_gen_snapshots`, then review `git diff tests/tests/snapshots` before committing.
//!
//! `browser` compiles every variant in headless Chromium against the WebGPU checks;
//! `driver_spirv` runs `spirv-val` on every variant's SPIR-V, which a Vulkan driver is given as
//! it is for the `sample_mask` variants.

#[path = "shaders_gen_snapshots/browser.rs"]
mod browser;
#[path = "shaders_gen_snapshots/driver_spirv.rs"]
mod driver_spirv;

#[test]
fn every_shaders_gen_variant_matches_its_wgsl_snapshot() {
    let mut seen = 0;
    for module in shaders_gen::MODULES {
        for variant in module.variants {
            insta::assert_snapshot!(format!("{}@{}", module.name, variant.name()), variant.wgsl);
            seen += 1;
        }
    }
    // 45 since the culling hierarchy: cull_prepare 12, tile_cull 6, cluster_cull 3 (the
    // scalarized culling variants are gone: they measured slower, BENCHMARKS.md).
    assert!(
        seen >= 45,
        "every module's variants are snapshotted ({seen})"
    );
}
