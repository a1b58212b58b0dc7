//! The unit tests of the text checks in `invariants.rs`: each invariant broken on purpose.

use super::*;

fn src(path: &str, text: &str) -> Vec<(String, String)> {
    vec![(path.to_owned(), text.to_owned())]
}

#[test]
fn wgpu_in_codegen_tree_is_a_violation() {
    let clean = "codegen v0.1.0 (/w/codegen)\nnaga v30.0.1\nsyn v2.0.119\n";
    assert_eq!(check_no_wgpu("codegen", clean), None);
    let broken = "codegen v0.1.0 (/w/codegen)\nwgpu v30.0.1\nwgpu-core v30.0.1\nnaga v30.0.1\n";
    let v = check_no_wgpu("codegen", broken).expect("wgpu must be caught");
    assert_eq!(v.invariant, "shader-dsl and codegen do not depend on wgpu");
    assert!(v.detail.contains("wgpu, wgpu-core"), "{}", v.detail);
}

#[test]
fn shader_dsl_may_only_depend_on_the_adapter_crates() {
    let clean = "shader-dsl v0.1.0\ncodegen v0.1.0\nproc-macro2 v1\nquote v1\nsyn v2\n";
    assert_eq!(check_shader_dsl_deps(clean), None);
    let broken = "shader-dsl v0.1.0\ncodegen v0.1.0\nnaga v30.0.1\nsyn v2\n";
    let v = check_shader_dsl_deps(broken).expect("naga must be caught");
    assert!(v.detail.contains("naga"), "{}", v.detail);
}

#[test]
fn a_fat_shader_dsl_is_a_violation() {
    let thin = src("lib.rs", "//! doc\nfn a() {}\n\n// comment\n");
    assert_eq!(check_shader_dsl_is_thin(&thin), None);
    let fat = src(
        "lib.rs",
        &"let x = 1;\n".repeat(SHADER_DSL_MAX_CODE_LINES + 1),
    );
    assert!(check_shader_dsl_is_thin(&fat).is_some());
}

#[test]
fn wgsl_in_renderer_is_a_violation() {
    let clean = src("pass.rs", "let m = shaders_gen::forward::variant(key);\n");
    assert!(check_no_shader_source(&clean).is_empty());
    let broken = src(
        "pass.rs",
        "ok\nconst S: &str = \"@compute @workgroup_size(64) fn f() {}\";\n",
    );
    let v = check_no_shader_source(&broken);
    assert_eq!(v.len(), 1);
    assert!(
        v[0].detail.starts_with("pass.rs:2: `@compute`"),
        "{}",
        v[0].detail
    );
}

#[test]
fn a_bind_group_built_by_hand_in_renderer_is_caught() {
    let clean = src(
        "pass.rs",
        "let g = forward::Group0 { camera }.bind_group(d, l, v, \"f\")?;\n",
    );
    assert!(check_no_hand_bound_groups(&clean).is_empty());
    let broken = src(
        "pass.rs",
        "ok\nlet g = device.create_bind_group(&desc);\nwgpu::BindGroupEntry { binding: 0, resource };\n",
    );
    let v = check_no_hand_bound_groups(&broken);
    assert_eq!(v.len(), 2);
    assert!(
        v[0].detail.starts_with("pass.rs:2: `create_bind_group(`"),
        "{}",
        v[0].detail
    );
}

#[test]
fn a_pass_begun_outside_the_pass_encoder_is_caught() {
    let sources = [
        src(
            "renderer/src/passes/tiles.rs",
            "let mut pass = ctx.encoder.begin_compute(\"tiles\");\n",
        ),
        src(
            "renderer/src/graph/encoder.rs",
            "let pass = self.encoder.begin_compute_pass(&desc);\n",
        ),
    ]
    .concat();
    assert!(check_passes_begin_through_the_pass_encoder(&sources).is_empty());
    let broken = src(
        "renderer/src/passes/sky.rs",
        "ok\nlet pass = ctx.encoder.begin_render_pass(&desc);\n",
    );
    let v = check_passes_begin_through_the_pass_encoder(&broken);
    assert_eq!(v.len(), 1);
    assert!(
        v[0].detail
            .starts_with("renderer/src/passes/sky.rs:2: `begin_render_pass(`"),
        "{}",
        v[0].detail
    );
}

#[test]
fn production_code_naming_the_culling_reference_is_caught() {
    let sources = [
        src(
            "culling/reference/methods.rs",
            "use super::Method;\nuse crate::culling::reference::cells;\n",
        ),
        src(
            "passes/depth_probe/capture.rs",
            "use crate::culling::depth::DepthBuffer;\n",
        ),
        src("passes/light_cull/mod.rs", "use crate::culling::Method;\n"),
    ]
    .concat();
    assert!(check_rendering_does_not_use_the_reference(&sources).is_empty());
    // The frame capture measures with `culling::depth` now, never the reference.
    let capture = src(
        "passes/depth_probe/capture.rs",
        "use crate::culling::reference::DepthBuffer;\n",
    );
    assert_eq!(
        check_rendering_does_not_use_the_reference(&capture).len(),
        1
    );
    let broken = src(
        "frame_data/lights.rs",
        "ok\nuse crate::culling::reference::LightSphere;\n",
    );
    let v = check_rendering_does_not_use_the_reference(&broken);
    assert_eq!(v.len(), 1);
    assert!(
        v[0].detail
            .starts_with("frame_data/lights.rs:2: `culling::reference`"),
        "{}",
        v[0].detail
    );
}
