//! Libraries and `#[invariant]` through the source-text API (no proc-macro): merging, the
//! library's own validation, axis checks, host re-exports, libraries that use libraries (the
//! graph: order, diamonds, cycles, clashes), the SPIR-V `Invariant` decoration, and the
//! bind-group builders emitted for modules and libraries (`builders`), and entry-point IO
//! structs a library declares for its users (`io_structs`), and materials (`#[material]`, a
//! `surface` function in a material frame: `materials`).

#[path = "libraries/builders.rs"]
mod builders;
#[path = "libraries/io_structs.rs"]
mod io_structs;
#[path = "libraries/materials.rs"]
mod materials;

const LIB: &str = r#"
#[library(axes(wide: bool = [false, true]))]
pub mod helpers {
    pub struct Pair { pub a: Vec4, pub b: f32 }
    pub const LIMIT: u32 = 16;
    pub fn width() -> u32 {
        select(wide, 8u32, 4u32)
    }
    pub fn unused_by_users(x: f32) -> f32 {
        x * 3.0
    }
}
"#;

fn user(axes: &str) -> String {
    format!(
        r#"
#[shader(axes({axes}), uses(crate::helpers))]
mod m {{
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [Pair];
    #[compute(workgroup_size(1))]
    fn main() {{
        OUT[0].b = (width() + LIMIT) as f32;
    }}
}}
"#
    )
}

fn err(src: &str) -> String {
    codegen::compile_source(src)
        .expect_err("must fail")
        .to_string()
}

#[test]
fn a_used_library_is_merged_and_its_host_items_are_re_exported() {
    let src = format!("{LIB}{}", user("wide: bool = [true]"));
    let c = codegen::compile_source(&src).unwrap_or_else(|e| panic!("{e}"));
    let wgsl = &c.variants[0].wgsl;
    assert!(wgsl.contains("fn width()"), "{wgsl}");
    // Only reachable library code is printed in a using module.
    assert!(!wgsl.contains("unused_by_users"), "{wgsl}");
    assert_eq!(c.libraries.len(), 1);
    assert_eq!(c.libraries[0].exports, ["Pair", "LIMIT"]);
    let host =
        codegen::emit::emit(&syn::parse_str::<syn::ItemMod>("mod m {}").unwrap(), &c).to_string();
    assert!(
        host.contains("pub use crate :: helpers :: { Pair , LIMIT }"),
        "{host}"
    );
    assert!(!host.contains("pub struct Pair"), "{host}");
}

#[test]
fn a_library_is_validated_on_its_own_with_every_function() {
    let file = syn::parse_file(LIB).unwrap();
    let (args, item) = codegen::library_modules(&file).remove(0);
    let c = codegen::compile_library(args, &item).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(c.keys.len(), 2);
    assert!(c.variants[0].wgsl.contains("fn unused_by_users"));
    let broken = LIB.replace("x * 3.0", "x * 3u32");
    let file = syn::parse_file(&broken).unwrap();
    let (args, item) = codegen::library_modules(&file).remove(0);
    let e = codegen::compile_library(args, &item).expect_err("broken library");
    assert!(e.to_string().contains("cannot apply `*`"), "{e}");
}

#[test]
fn library_axes_must_be_declared_with_supported_values() {
    let missing = err(&format!("{LIB}{}", user("msaa: u32 = [1]")));
    assert!(
        missing.contains(
            "library `helpers` needs axis `wide: bool`; declare it in this module's `axes(..)`"
        ),
        "{missing}"
    );
    let retyped = err(&format!("{LIB}{}", user("wide: u32 = [1]")));
    assert!(retyped.contains("declares it as `u32`"), "{retyped}");
    let lib = LIB.replace("[false, true]", "[true]");
    let extra = err(&format!("{lib}{}", user("wide: bool = [false, true]")));
    assert!(
        extra.contains("takes the values [false] here, which library `helpers` does not support"),
        "{extra}"
    );
}

#[test]
fn clashes_entry_points_and_paths_are_errors() {
    let clash = err(&format!(
        "{LIB}{}",
        user("wide: bool = [true]").replace("mod m {", "mod m {\n    const LIMIT: u32 = 1;")
    ));
    assert!(
        clash.contains("the name `LIMIT` is defined both in library `helpers` and in this module"),
        "{clash}"
    );
    let entry = LIB.replace(
        "pub fn width()",
        "#[compute(workgroup_size(1))]\n    pub fn width()",
    );
    let file = syn::parse_file(&entry).unwrap();
    let (args, item) = codegen::library_modules(&file).remove(0);
    let e = codegen::compile_library(args, &item).expect_err("entry point");
    assert!(
        e.to_string().contains("a library has no entry points"),
        "{e}"
    );
    let nested = LIB.replace("#[library(", "#[library(uses(crate::other), ");
    let file = syn::parse_file(&nested).unwrap();
    let (args, item) = codegen::library_modules(&file).remove(0);
    let e = codegen::compile_library(args.clone(), &item).expect_err("its library is missing");
    assert!(
        e.to_string().contains("no library `other` was found"),
        "{e}"
    );
    let e = codegen::compile_library_with_libraries(args, &item, &[]).expect_err("missing");
    assert!(
        e.to_string()
            .contains("no `#[library]` module named `other` in the sources given"),
        "{e}"
    );
    let unknown = err(&user("wide: bool = [true]"));
    assert!(
        unknown.contains("no `#[library]` module named `helpers`"),
        "{unknown}"
    );
}

const VERTEX: &str = r#"
#[shader]
mod m {
    pub struct VsOut {
        #[builtin(position)]
        #[invariant]
        pub clip: Vec4,
        #[location(0)]
        pub uv: Vec2,
    }
    #[vertex]
    fn vs(#[location(0)] p: Vec4) -> VsOut {
        VsOut { clip: p, uv: p.xy() }
    }
    #[fragment]
    fn fs(input: VsOut) -> Vec4 {
        input.uv.extend(0.0).extend(1.0)
    }
}
"#;

/// `OpDecorate <id> Invariant`: opcode 71, three words, decoration 18.
fn has_invariant_decoration(words: &[u32]) -> bool {
    let mut i = 5;
    while i < words.len() {
        let (count, op) = ((words[i] >> 16) as usize, words[i] & 0xffff);
        if op == 71 && count == 3 && words[i + 2] == 18 {
            return true;
        }
        i += count.max(1);
    }
    false
}

#[test]
fn invariant_positions_are_decorated_in_wgsl_and_spirv() {
    let c = codegen::compile_source(VERTEX).unwrap_or_else(|e| panic!("{e}"));
    let v = &c.variants[0];
    assert!(
        v.wgsl
            .contains("@builtin(position) @invariant clip: vec4<f32>"),
        "{}",
        v.wgsl
    );
    assert!(has_invariant_decoration(&v.spirv));
    let plain = codegen::compile_source(&VERTEX.replace("#[invariant]", "")).unwrap();
    assert!(!has_invariant_decoration(&plain.variants[0].spirv));
    let ret = "#[shader]\nmod m {\n    #[vertex]\n    #[invariant]\n    fn vs(#[location(0)] p: Vec4) -> Vec4 {\n        p\n    }\n}\n";
    let c = codegen::compile_source(ret).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        c.variants[0].wgsl.contains("@invariant"),
        "{}",
        c.variants[0].wgsl
    );
    assert!(has_invariant_decoration(&c.variants[0].spirv));
    let misplaced = err(&VERTEX.replace(
        "#[invariant]\n        pub clip: Vec4,\n        #[location(0)]",
        "pub clip: Vec4,\n        #[location(0)]\n        #[invariant]",
    ));
    assert!(
        misplaced.contains("`#[invariant]` applies only to the position"),
        "{misplaced}"
    );
}

#[test]
fn a_library_struct_must_keep_its_layout_in_the_using_module() {
    let lib = r#"
#[library]
pub mod shapes {
    pub struct Inner { pub a: f32 }
    pub struct Outer { pub inner: Inner, pub b: f32 }
}
"#;
    let module = |space: &str| {
        format!(
            r#"
#[shader(uses(crate::shapes))]
mod m {{
    #[{space}(group = 0, binding = 0)]
    static U: Outer;
    #[storage(group = 0, binding = 1, read_write)]
    static OUT: [f32];
    #[compute(workgroup_size(1))]
    fn main() {{
        OUT[0] = U.b;
    }}
}}
"#
        )
    };
    // A storage buffer keeps the library's (non-uniform) layout; a uniform buffer would move
    // `b` to offset 16 and break the library's host type.
    codegen::compile_source(&format!("{lib}{}", module("storage")))
        .unwrap_or_else(|e| panic!("{e}"));
    let e = err(&format!("{lib}{}", module("uniform")));
    assert!(
        e.contains("struct `Outer` of library `shapes` gets a different memory layout"),
        "{e}"
    );
}

/// A graph: `base` at the bottom, `left` and `right` both use it, `top` uses `left` (so it
/// reaches `base` only through it).
const GRAPH: &str = r#"
#[library(axes(wide: bool = [false, true]))]
pub mod base {
    pub struct Sample { pub value: Vec4 }
    pub const SCALE: f32 = 2.0;
    pub fn scaled(x: f32) -> f32 {
        x * select(wide, SCALE, 1.0)
    }
}
#[library(axes(wide: bool = [false, true]), uses(crate::base))]
pub mod left {
    pub const OFFSET: f32 = SCALE + 1.0;
    pub fn left_of(s: Sample) -> f32 {
        scaled(s.value.x) + OFFSET
    }
}
#[library(axes(wide: bool = [false, true]), uses(crate::base))]
pub mod right {
    pub struct Pairing { pub first: Sample, pub weight: f32 }
    pub fn right_of(p: Pairing) -> f32 {
        scaled(p.first.value.y) * p.weight
    }
}
"#;

fn graph_user(uses: &str, axes: &str, body: &str) -> String {
    format!(
        r#"{GRAPH}
#[shader(axes({axes}), uses({uses}))]
mod m {{
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [f32];
    #[storage(group = 0, binding = 1)]
    static IN: [Sample];
    #[compute(workgroup_size(1))]
    fn main() {{
        {body}
    }}
}}
"#
    )
}

fn library_named(src: &str, name: &str) -> (proc_macro2::TokenStream, syn::ItemMod) {
    let file = syn::parse_file(src).unwrap();
    codegen::library_modules(&file)
        .into_iter()
        .find(|(_, m)| m.ident == name)
        .unwrap()
}

#[test]
fn a_library_that_uses_a_library_brings_it_along() {
    // The module names only `left`; `base` comes with it, before it.
    let src = graph_user(
        "crate::left",
        "wide: bool = [true]",
        "OUT[0] = left_of(IN[0]) + scaled(1.0);",
    );
    let c = codegen::compile_source(&src).unwrap_or_else(|e| panic!("{e}"));
    let wgsl = &c.variants[0].wgsl;
    assert!(
        wgsl.contains("fn scaled(") && wgsl.contains("fn left_of("),
        "{wgsl}"
    );
    let order: Vec<String> = c
        .libraries
        .iter()
        .map(|l| l.path.segments.last().unwrap().ident.to_string())
        .collect();
    assert_eq!(order, ["base", "left"]);
    // Each library exports its own host items only; the module re-exports both.
    assert_eq!(c.libraries[0].exports, ["Sample", "SCALE"]);
    assert_eq!(c.libraries[1].exports, ["OFFSET"]);
    let host =
        codegen::emit::emit(&syn::parse_str::<syn::ItemMod>("mod m {}").unwrap(), &c).to_string();
    assert!(
        host.contains("pub use crate :: base :: { Sample , SCALE }"),
        "{host}"
    );
    assert!(
        host.contains("pub use crate :: left :: { OFFSET }"),
        "{host}"
    );
    assert!(!host.contains("pub struct Sample"), "{host}");
}

#[test]
fn a_diamond_merges_its_shared_library_once() {
    let src = graph_user(
        "crate::left, crate::right",
        "wide: bool = [false, true]",
        "OUT[0] = left_of(IN[0]) + right_of(Pairing { first: IN[0], weight: 0.5 });",
    );
    let c = codegen::compile_source(&src).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(c.variants.len(), 2);
    for v in &c.variants {
        assert_eq!(v.wgsl.matches("fn scaled(").count(), 1, "{}", v.wgsl);
        assert_eq!(v.wgsl.matches("struct Sample").count(), 1, "{}", v.wgsl);
    }
    assert_eq!(c.libraries.len(), 3);
}

#[test]
fn a_library_is_validated_once_with_the_libraries_it_uses() {
    let file = syn::parse_file(GRAPH).unwrap();
    let available = codegen::library_modules(&file);
    let (args, item) = library_named(GRAPH, "left");
    let c = codegen::compile_library_with_libraries(args, &item, &available)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(c.keys.len(), 2);
    assert!(
        c.variants[1].wgsl.contains("fn left_of(") && c.variants[1].wgsl.contains("fn scaled(")
    );
    // Its host items are its own; `base`'s are re-exported from `base`.
    let host = codegen::emit::library_host_items(&c).to_string();
    assert!(
        host.contains("pub use crate :: base :: { Sample , SCALE }"),
        "{host}"
    );
    assert!(host.contains("pub const OFFSET"), "{host}");
    // An error in the library is reported although nothing uses it.
    let broken = GRAPH.replace("scaled(s.value.x) + OFFSET", "scaled(s.value.x) + 1u32");
    let file = syn::parse_file(&broken).unwrap();
    let available = codegen::library_modules(&file);
    let (args, item) = library_named(&broken, "left");
    let e = codegen::compile_library_with_libraries(args, &item, &available).expect_err("broken");
    assert!(e.to_string().contains("cannot apply `+`"), "{e}");
}

#[test]
fn a_cycle_in_the_library_graph_is_an_error_naming_its_route() {
    let cyclic = GRAPH.replace(
        "#[library(axes(wide: bool = [false, true]))]\npub mod base {",
        "#[library(axes(wide: bool = [false, true]), uses(crate::left))]\npub mod base {",
    );
    assert_ne!(cyclic, GRAPH);
    let e = codegen::compile_source(&format!(
        "{cyclic}{}",
        graph_user("crate::left", "wide: bool = [true]", "OUT[0] = 1.0;").replace(GRAPH, "")
    ))
    .expect_err("cycle")
    .to_string();
    assert_eq!(
        e,
        "library cycle: crate::left → crate::base → crate::left; a library graph must have no cycles"
    );
    // The library itself reports the cycle through it.
    let file = syn::parse_file(&cyclic).unwrap();
    let available = codegen::library_modules(&file);
    let (args, item) = library_named(&cyclic, "left");
    let e = codegen::compile_library_with_libraries(args, &item, &available)
        .expect_err("cycle")
        .to_string();
    assert_eq!(
        e,
        "library cycle: `left` uses itself through crate::base → crate::left; a library graph must have no cycles"
    );
}

#[test]
fn clashes_and_axes_name_the_route_through_the_graph() {
    let clash = err(
        &graph_user("crate::left", "wide: bool = [true]", "OUT[0] = 1.0;")
            .replace("mod m {", "mod m {\n    const SCALE: f32 = 1.0;"),
    );
    assert!(
        clash.contains("the name `SCALE` is defined both in library `base` (used through crate::left → crate::base) and in this module"),
        "{clash}"
    );
    let axis = err(&graph_user(
        "crate::right",
        "msaa: u32 = [1]",
        "OUT[0] = 1.0;",
    ));
    assert!(
        axis.contains(
            "library `base` (used through crate::right → crate::base) needs axis `wide: bool`"
        ),
        "{axis}"
    );
}

/// A library's bindings in a group that no entry point of a variant uses are left out of that
/// variant (its WGSL and its layout); a group the variant uses keeps every library binding,
/// used or not, as the host binds it.
#[test]
fn a_library_group_no_entry_point_uses_is_left_out_of_the_variant() {
    let src = r#"
#[library]
pub mod mats {
    #[storage(group = 0, binding = 1)]
    static SHARED: [f32];
    #[storage(group = 2, binding = 0)]
    static MATS: [f32];
    pub fn mat(i: u32) -> f32 {
        MATS[i]
    }
}

#[shader(axes(masked: bool = [false, true]), uses(crate::mats))]
mod m {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [f32];
    #[compute(workgroup_size(1))]
    fn main() {
        if masked {
            OUT[0] = mat(0u32);
        } else {
            OUT[0] = 1.0;
        }
    }
}
"#;
    let c = codegen::compile_source(src).unwrap_or_else(|e| panic!("{e}"));
    let bindings = |masked: usize| -> Vec<(u32, u32)> {
        let v = &c.variants[c.key_variant[masked].expect("variant")];
        v.reflection
            .bindings
            .iter()
            .map(|b| (b.group, b.binding))
            .collect()
    };
    // Group 0 is used (OUT), so the library's unused SHARED stays; group 2 only where read.
    assert_eq!(bindings(0), [(0, 0), (0, 1)]);
    assert_eq!(bindings(1), [(0, 0), (0, 1), (2, 0)]);
    let plain = &c.variants[c.key_variant[0].expect("variant")].wgsl;
    assert!(!plain.contains("MATS"), "{plain}");
    assert!(plain.contains("SHARED"), "{plain}");
}
