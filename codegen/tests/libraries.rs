//! Libraries and `#[invariant]` through the source-text API (no proc-macro): merging, the
//! library's own validation, axis checks, host re-exports, and the SPIR-V `Invariant`
//! decoration.

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
    let e = codegen::compile_library(args, &item).expect_err("library using a library");
    assert!(e.to_string().contains("cannot use another library"), "{e}");
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
