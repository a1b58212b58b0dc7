//! Stage-level tests of the compiler, without the proc-macro: front-end errors, texture
//! sampling methods, variant enumeration, naming, pruning and dedup, the source map, layouts
//! and reflection; `u64` and 64-bit atomics (`int64`).

#[path = "stages/int64.rs"]
mod int64;
#[path = "stages/workgroup_memory.rs"]
mod workgroup_memory;

use codegen::rt::{BindingKind, SampleType};

fn compile(src: &str) -> codegen::Compiled {
    codegen::compile_source(src).unwrap_or_else(|e| {
        let at = e.span().start();
        panic!("{}:{}: {e}", at.line, at.column)
    })
}

/// Asserts that `src` fails with a message containing `msg` at `line:column` (1-based line,
/// 0-based column, as proc_macro2 reports them).
fn check_err(src: &str, msg: &str, line: usize, column: usize) {
    let e = codegen::compile_source(src).expect_err("must fail");
    let at = e.span().start();
    assert!(e.to_string().contains(msg), "message `{e}` lacks `{msg}`");
    assert_eq!((at.line, at.column), (line, column), "span of `{e}`");
}

fn kernel(body: &str) -> String {
    format!(
        "#[shader]\nmod m {{\n    #[storage(group = 0, binding = 0, read_write)]\n    static OUT: [u32];\n    #[compute(workgroup_size(1))]\n    fn main(#[builtin(global_invocation_id)] gid: UVec3) {{\n{body}\n    }}\n}}\n"
    )
}

#[test]
fn front_end_errors_point_at_the_construct() {
    check_err(
        &kernel("        let f = |x: u32| x;"),
        "closures are not supported",
        7,
        16,
    );
    check_err(
        &kernel("        let x = 1u32;\n        let r = &x;"),
        "references are only allowed",
        8,
        16,
    );
    check_err(
        &kernel("        OUT[gid.x] = 1.5;"),
        "mismatched types: expected `u32`, found `{float}`",
        7,
        21,
    );
    check_err(
        &kernel("        let v = Vec3::ONE.wobble();"),
        "unknown method `wobble` on `Vec3`",
        7,
        26,
    );
    check_err(
        &kernel("        let n: i64 = 0;"),
        "`i64` is not supported in shader code: the DSL's only 64-bit integer is `u64` (needs wgpu's SHADER_INT64); use `u64` or `i32`",
        7,
        15,
    );
    check_err(
        &kernel("        loop { }\n        break;"),
        "`break` outside of a loop",
        8,
        8,
    );
    check_err(
        &kernel("        let x = 1u32;\n        x = 2u32;"),
        "not declared `mut`",
        8,
        8,
    );
    check_err(
        &kernel("        let v = Vec3::new(1.0, 2.0);"),
        "needs 3 components in total, found 2",
        7,
        16,
    );
    check_err(
        &kernel("        let a = Vec3::ONE < Vec3::ZERO;"),
        "comparing vectors is not supported",
        7,
        26,
    );
}

#[test]
fn enumeration_names_exclusion_and_order() {
    let c = compile(
        r#"#[shader(axes(tile: u32 = [8, 16] => "t", neg: i32 = [-1, 2], fast: bool = [false, true]), exclude(tile == 16 && fast))]
mod m {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [i32];
    #[compute(workgroup_size(tile))]
    fn main(#[builtin(global_invocation_id)] gid: UVec3) {
        if fast {
            OUT[gid.x] = neg * 2;
        } else {
            OUT[gid.x] = neg;
        }
    }
}"#,
    );
    let names: Vec<&str> = c.keys.iter().map(|k| k.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "t8_negm1",
            "t8_negm1_fast",
            "t8_neg2",
            "t8_neg2_fast",
            "t16_negm1",
            "t16_negm1_fast",
            "t16_neg2",
            "t16_neg2_fast"
        ]
    );
    let excluded: Vec<bool> = c.keys.iter().map(|k| k.excluded).collect();
    assert_eq!(
        excluded,
        [false, false, false, false, false, true, false, true]
    );
    assert_eq!(c.variants.len(), 6);
    // Pruning: the `fast` branch exists only where `fast` is true, with the axis folded in.
    let fast = &c.variants[1].wgsl;
    assert!(fast.contains("OUT[gid.x] = -2i;"), "{fast}");
    assert!(!fast.contains("if "), "{fast}");
    assert!(c.variants[0].wgsl.contains("OUT[gid.x] = -1i;"));
}

#[test]
fn identical_variants_are_deduplicated() {
    let c = compile(
        r#"#[shader(axes(unused: bool = [false, true], tile: u32 = [4, 8]))]
mod m {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [u32];
    #[compute(workgroup_size(tile))]
    fn main(#[builtin(local_invocation_index)] i: u32) {
        OUT[i] = i;
    }
}"#,
    );
    assert_eq!(c.keys.len(), 4);
    assert_eq!(c.variants.len(), 2);
    assert_eq!(c.variants[0].names, ["tile4", "unused_tile4"]);
    assert_eq!(c.key_variant, [Some(0), Some(1), Some(0), Some(1)]);
}

#[test]
fn unreachable_helpers_are_left_out() {
    let c = compile(
        r#"#[shader(axes(wave: bool = [false, true]), requires(subgroup = wave))]
mod m {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [u32];
    fn wave_sum(x: u32) -> u32 {
        subgroup_add(x)
    }
    #[compute(workgroup_size(64))]
    fn main(#[builtin(local_invocation_index)] i: u32) {
        let mut v = i;
        if wave {
            v = wave_sum(v);
        }
        OUT[i] = v;
    }
}"#,
    );
    assert!(!c.variants[0].wgsl.contains("wave_sum"));
    assert!(c.variants[1].wgsl.contains("fn wave_sum"));
    assert!(!c.variants[0].reflection.features.subgroup);
    assert!(c.variants[1].reflection.features.subgroup);
}

#[test]
fn source_map_finds_the_rust_span_of_printed_code() {
    let src = kernel("        let doubled = gid.x * 2u32;\n        OUT[gid.x] = doubled;");
    let c = compile(&src);
    let v = &c.variants[0];
    let at = v.wgsl.find("gid.x * 2u").expect("printed");
    let span = v
        .source_map
        .lookup(at..at + "gid.x * 2u".len())
        .expect("mapped");
    // Binary expressions are located at their operator.
    assert_eq!((span.start().line, span.start().column), (7, 28));
    let at = v.wgsl.find("OUT[gid.x] = doubled").expect("printed");
    let span = v.source_map.lookup(at..at + 3).expect("mapped");
    assert_eq!(span.start().line, 8);
}

#[test]
fn layouts_follow_wgsl_and_uniform_rules() {
    let c = compile(
        r#"#[shader]
mod m {
    pub struct Inner { pub a: f32 }
    pub struct Outer { pub v: Vec3, pub s: f32, pub inner: Inner, pub after: u32, pub m: Mat3 }
    #[uniform(group = 0, binding = 0)]
    static U: Outer;
    #[compute(workgroup_size(1))]
    fn main() {
        let x = U.v;
    }
}"#,
    );
    let m = &c.module;
    let env = &c.keys[0].env;
    let outer = codegen::layout::struct_layout(1, m, env);
    let offsets: Vec<u32> = outer.members.iter().map(|x| x.offset).collect();
    // vec3 + f32 share 16 bytes; the nested struct is 16-aligned and 16-sized in uniforms.
    assert_eq!(offsets, [0, 12, 16, 32, 48]);
    assert_eq!((outer.layout.size, outer.layout.align), (96, 16));
    assert_eq!(outer.members[2].align_attr, Some(16));
    assert!(
        c.variants[0]
            .wgsl
            .contains("@align(16) @size(16) inner: Inner,")
    );
    // naga agrees.
    let naga = c.naga_layouts[1].as_ref().expect("naga layout");
    assert_eq!(naga.offsets, offsets);
    assert_eq!((naga.size, naga.align), (96, 16));
}

#[test]
fn reflection_of_bindings_and_entry_points() {
    let c = compile(
        r#"#[shader(axes(msaa: u32 = [1, 4]))]
mod m {
    #[uniform(group = 1, binding = 0)]
    static U: Vec4;
    #[texture(group = 0, binding = 1)]
    #[when(msaa == 1)]
    static DEPTH: TextureDepth2d;
    #[texture(group = 0, binding = 1)]
    #[when(msaa > 1)]
    static DEPTH_MS: TextureDepthMultisampled2d;
    #[storage(group = 0, binding = 0)]
    static DATA: [Vec4];
    #[vertex]
    fn vs(#[builtin(vertex_index)] i: u32) -> Vec4 {
        DATA[i]
    }
    #[fragment]
    fn fs(#[builtin(position)] p: Vec4) -> Vec4 {
        let mut d = 0.0;
        if msaa == 1 {
            d = DEPTH.load(p.xy().as_uvec2(), 0u32);
        } else {
            d = DEPTH_MS.load(p.xy().as_uvec2(), 0u32);
        }
        U * d
    }
}"#,
    );
    let single = &c.variants[0].reflection;
    let keys: Vec<(u32, u32, &str)> = single
        .bindings
        .iter()
        .map(|b| (b.group, b.binding, b.name.as_str()))
        .collect();
    assert_eq!(keys, [(0, 0, "DATA"), (0, 1, "DEPTH"), (1, 0, "U")]);
    assert!(single.bindings[0].visibility.vertex && !single.bindings[0].visibility.fragment);
    assert!(matches!(
        single.bindings[0].kind,
        BindingKind::Storage {
            read_only: true,
            min_size: 16
        }
    ));
    assert!(matches!(
        single.bindings[1].kind,
        BindingKind::Texture {
            sample_type: SampleType::Depth,
            multisampled: false,
            ..
        }
    ));
    let ms = &c.variants[1].reflection;
    assert_eq!(ms.bindings[1].name, "DEPTH_MS");
    assert!(matches!(
        ms.bindings[1].kind,
        BindingKind::Texture {
            multisampled: true,
            ..
        }
    ));
    assert_eq!(single.entry_points.len(), 2);
    assert_eq!(single.entry_points[0].workgroup_size, [0, 0, 0]);
    let color = codegen::rt::Location {
        location: 0,
        format: codegen::rt::ValueFormat::Float32x4,
    };
    assert_eq!(single.entry_points[1].outputs, [color]);
    assert!(single.entry_points[0].inputs.is_empty());
}

#[test]
fn naga_errors_map_back_and_name_the_variant() {
    let src = "#[shader(axes(n: u32 = [1, 0]))]\nmod m {\n    #[storage(group = 0, binding = 0, read_write)]\n    static OUT: [u32];\n    #[compute(workgroup_size(1))]\n    fn main() {\n        OUT[0] = 7u32 / n;\n    }\n}\n";
    let e = codegen::compile_source(src).expect_err("division by zero in variant n0");
    let msg = e.to_string();
    assert!(msg.contains("variant `n0`"), "{msg}");
    assert_eq!(e.span().start().line, 7);
}

/// A fragment shader with one texture and sampler of each kind `sample_grad` must refuse or
/// accept; `body` is its first statement, at line 19 (the function returns `Vec4::ZERO`).
fn sampling(body: &str) -> String {
    format!(
        "#[shader]\nmod m {{\n    #[texture(group = 0, binding = 0)]\n    static T: Texture2d<f32>;\n    #[texture(group = 0, binding = 1)]\n    static ARR: Texture2dArray<f32>;\n    #[texture(group = 0, binding = 2)]\n    static DEPTH: TextureDepth2d;\n    #[texture(group = 0, binding = 3)]\n    static MS: TextureMultisampled2d<f32>;\n    #[texture(group = 0, binding = 4, unfilterable)]\n    static IDS: Texture2d<u32>;\n    #[sampler(group = 0, binding = 5)]\n    static S: Sampler;\n    #[sampler(group = 0, binding = 6)]\n    static CMP: SamplerComparison;\n    #[fragment]\n    fn fs(#[location(0)] uv: Vec2, #[location(1)] #[interpolate(flat)] layer: u32) -> Vec4 {{\n{body}\n        Vec4::ZERO\n    }}\n}}\n"
    )
}

#[test]
fn sample_grad_prints_texture_sample_grad() {
    let c = compile(&sampling(
        "        let a = T.sample_grad(S, uv, dpdx(uv), dpdy(uv)) + ARR.sample_grad(S, uv, layer, Vec2::X, Vec2::Y);",
    ));
    let wgsl = &c.variants[0].wgsl;
    assert!(
        wgsl.contains("textureSampleGrad(T, S, uv, dpdx(uv), dpdy(uv))"),
        "{wgsl}"
    );
    assert!(
        wgsl.contains(
            "textureSampleGrad(ARR, S, uv, layer, vec2<f32>(1.0f, 0.0f), vec2<f32>(0.0f, 1.0f))"
        ),
        "{wgsl}"
    );
}

#[test]
fn sample_grad_refuses_what_wgsl_has_no_overload_for() {
    for (body, msg, column) in [
        (
            "DEPTH.sample_grad(S, uv, uv, uv)",
            "`TextureDepth2d` cannot be sampled with `sample_grad` (WGSL has no gradient sampling of depth textures); use `sample_level`",
            22,
        ),
        (
            "MS.sample_grad(S, uv, uv, uv)",
            "`TextureMultisampled2d<f32>` cannot be sampled with `sample_grad`; use `load`",
            19,
        ),
        (
            "IDS.sample_grad(S, uv, uv, uv)",
            "`Texture2d<u32>` cannot be sampled with `sample_grad`; use `load`",
            20,
        ),
        (
            "T.sample_grad(CMP, uv, uv, uv)",
            "expected a `Sampler` static, found `SamplerComparison`",
            30,
        ),
        (
            "T.sample_grad(S, uv, uv)",
            "expected `sample_grad(sampler, uv: Vec2, ddx: Vec2, ddy: Vec2)` for `Texture2d<f32>`",
            16,
        ),
        (
            "T.sample_grad(S, uv, 1.0, 1.0)",
            "expected `sample_grad(sampler, uv: Vec2, ddx: Vec2, ddy: Vec2)` for `Texture2d<f32>`",
            16,
        ),
        (
            "ARR.sample_grad(S, uv, uv, uv)",
            "expected `sample_grad(sampler, uv: Vec2, layer: u32, ddx: Vec2, ddy: Vec2)` for `Texture2dArray<f32>`",
            16,
        ),
        (
            "ARR.sample_grad(S, uv, 0.5, uv, uv)",
            "expected `sample_grad(sampler, uv: Vec2, layer: u32, ddx: Vec2, ddy: Vec2)` for `Texture2dArray<f32>`",
            16,
        ),
    ] {
        check_err(
            &sampling(&format!("        let c = {body};")),
            msg,
            19,
            column,
        );
    }
}

#[test]
fn sample_grad_needs_no_fragment_stage_but_sample_does() {
    let src = |call: &str| {
        format!(
            "#[shader]\nmod m {{\n    #[texture(group = 0, binding = 0)]\n    static T: Texture2d<f32>;\n    #[sampler(group = 0, binding = 1)]\n    static S: Sampler;\n    #[storage(group = 0, binding = 2, read_write)]\n    static OUT: [Vec4];\n    #[compute(workgroup_size(1))]\n    fn main(#[builtin(global_invocation_id)] gid: UVec3) {{\n        OUT[gid.x] = {call};\n    }}\n}}\n"
        )
    };
    let c = compile(&src("T.sample_grad(S, Vec2::ZERO, Vec2::X, Vec2::Y)"));
    assert!(c.variants[0].wgsl.contains("textureSampleGrad("));
    // Implicit derivatives exist only in fragment shaders: naga refuses the entry point.
    let e = codegen::compile_source(&src("T.sample(S, Vec2::ZERO)")).expect_err("compute stage");
    assert!(e.to_string().contains("forbidden at this stage"), "{e}");
}

/// `unless`: an axis value that adds nothing to variant names, so an axis added to a module
/// keeps its variants' names (and snapshots) at that value; and `#[when(..)]` on entry points:
/// an entry point, with what only it uses, exists only where its predicate holds.
#[test]
fn unnamed_axis_values_and_entry_points_under_when() {
    let c = compile(
        r#"#[shader(axes(fast: bool = [false, true], msaa: u32 = [0, 4] => "msaa" unless 0))]
mod m {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [u32];
    #[storage(group = 0, binding = 1, read_write)]
    #[when(msaa > 0)]
    static SAMPLES: [u32];
    fn doubled(x: u32) -> u32 {
        x * 2u32
    }
    #[compute(workgroup_size(1))]
    #[when(msaa == 0)]
    fn plain(#[builtin(global_invocation_id)] gid: UVec3) {
        OUT[gid.x] = gid.x;
    }
    #[compute(workgroup_size(1))]
    #[when(msaa > 0)]
    fn resolve(#[builtin(global_invocation_id)] gid: UVec3) {
        OUT[gid.x] = doubled(SAMPLES[gid.x] + msaa);
    }
}"#,
    );
    let names: Vec<&str> = c.keys.iter().map(|k| k.name.as_str()).collect();
    assert_eq!(names, ["default", "msaa4", "fast", "fast_msaa4"]);
    fn entries(v: &codegen::CompiledVariant) -> Vec<&str> {
        v.reflection
            .entry_points
            .iter()
            .map(|e| e.name.as_str())
            .collect()
    }
    let plain = &c.variants[0];
    assert_eq!(entries(plain), ["plain"]);
    assert!(!plain.wgsl.contains("fn resolve"), "{}", plain.wgsl);
    assert!(!plain.wgsl.contains("fn doubled"), "{}", plain.wgsl);
    assert_eq!(plain.reflection.bindings.len(), 1);
    let resolve = &c.variants[1];
    assert_eq!(entries(resolve), ["resolve"]);
    assert!(!resolve.wgsl.contains("fn plain"), "{}", resolve.wgsl);
    assert_eq!(resolve.reflection.bindings.len(), 2);
}

#[test]
fn when_on_a_helper_and_bad_unless_values_are_errors() {
    check_err(
        "#[shader]\nmod m {\n    #[when(true)]\n    fn helper() -> u32 {\n        1u32\n    }\n}\n",
        "belongs on an entry point",
        3,
        6,
    );
    check_err(
        "#[shader(axes(fast: bool = [false, true] => \"fast\" unless false))]\nmod m {}\n",
        "a `bool` axis adds its label only when `true`",
        1,
        58,
    );
    check_err(
        "#[shader(axes(msaa: u32 = [1, 4] => \"msaa\" unless 2))]\nmod m {}\n",
        "`unless` takes one of the axis' own values",
        1,
        50,
    );
}
