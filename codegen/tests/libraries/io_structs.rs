//! Entry-point IO structs declared by a library, for the modules that use it.

const LIB: &str = r#"
#[library]
pub mod varyings {
    pub struct Varying {
        #[builtin(position)]
        #[invariant]
        pub clip: Vec4,
        #[location(0)]
        pub uv: Vec2,
    }
    pub fn brighten(v: Varying) -> f32 {
        v.uv.x * 2.0
    }
}
"#;

#[test]
fn a_library_io_struct_serves_a_module_entry_point() {
    let src = format!(
        "{LIB}{}",
        r#"
#[shader(uses(crate::varyings))]
mod draw {
    #[vertex]
    fn vs(#[location(0)] p: Vec3) -> Varying {
        Varying { clip: p.extend(1.0), uv: p.xy() }
    }
    #[fragment]
    fn fs(input: Varying) -> Vec4 {
        Vec4::splat(brighten(input))
    }
}
"#
    );
    let c = codegen::compile_source(&src).unwrap_or_else(|e| panic!("{e}"));
    let wgsl = &c.variants[0].wgsl;
    assert!(wgsl.contains("@location(0) uv: vec2<f32>"), "{wgsl}");
    assert!(wgsl.contains("@builtin(position) @invariant"), "{wgsl}");
}

#[test]
fn a_module_that_does_not_use_the_library_io_struct_still_compiles() {
    let src = format!(
        "{LIB}{}",
        r#"
#[shader(uses(crate::varyings))]
mod other {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [f32];
    #[compute(workgroup_size(1))]
    fn main() {
        OUT[0] = 1.0;
    }
}
"#
    );
    codegen::compile_source(&src).unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn a_module_own_struct_with_io_attributes_must_still_be_io() {
    let src = r#"
#[shader]
mod own {
    struct NotIo {
        #[location(0)]
        uv: Vec2,
    }
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [f32];
    #[compute(workgroup_size(1))]
    fn main() {
        let n = NotIo { uv: Vec2::ZERO };
        OUT[0] = n.uv.x;
    }
}
"#;
    let e = codegen::compile_source(src)
        .expect_err("must fail")
        .to_string();
    assert!(
        e.contains("only make sense on entry point IO structs"),
        "{e}"
    );
}
