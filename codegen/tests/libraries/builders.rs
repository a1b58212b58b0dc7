//! The emitted bind-group builders: a module's own fields, a library's part, a `#[when]`
//! binding as an `Option`, the library's own builder, `builder_field`, and the name clash.

use super::library_named;

#[test]
fn bind_group_builders_hold_own_fields_and_each_library_part() {
    let src = r#"
#[library]
pub mod frame_lib {
    #[uniform(group = 0, binding = 3)]
    static FRAME: Vec4;
    pub fn frame() -> Vec4 { FRAME }
}
#[shader(axes(extra: bool = [false, true]), uses(crate::frame_lib))]
mod m {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [Vec4];
    #[storage(group = 1, binding = 2)]
    #[when(extra)]
    static MORE: [Vec4];
    #[compute(workgroup_size(1))]
    fn main() {
        OUT[0] = frame();
        if extra {
            OUT[1] = MORE[0];
        }
    }
}
"#;
    let c = codegen::compile_source(src).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(c.libraries[0].groups, [0]);
    assert_eq!(c.libraries[0].bindings, ["FRAME"]);
    let field = |name| codegen::emit::builder_field(&c, name);
    assert_eq!(field("OUT").as_deref(), Some("Group0.out"));
    assert_eq!(field("FRAME").as_deref(), Some("Group0.frame_lib.frame"));
    assert_eq!(field("MORE").as_deref(), Some("Group1.more"));
    let host = codegen::emit::emit(&syn::parse_str::<syn::ItemMod>("mod m {}").unwrap(), &c)
        .to_string()
        .replace(' ', "");
    for needed in [
        "pubstructGroup0<'a>",
        "pubout:::shader_bind::wgpu::BufferBinding<'a>",
        "pubframe_lib:crate::frame_lib::Group0<'a>",
        "pubmore:::core::option::Option<::shader_bind::wgpu::BufferBinding<'a>>",
        "out.push(\"OUT\"",
        "::shader_bind::GroupResources::collect(&self.frame_lib,out)",
    ] {
        assert!(host.contains(needed), "missing {needed} in {host}");
    }
    // The library's own builder holds its binding alone.
    let lib_src = &src[..src.find("#[shader").unwrap()];
    let (args, item) = library_named(lib_src, "frame_lib");
    let lib = codegen::compile_library(args, &item).unwrap_or_else(|e| panic!("{e}"));
    let lib_host = codegen::emit::library_host_items(&lib)
        .to_string()
        .replace(' ', "");
    assert!(
        lib_host.contains("pubframe:::shader_bind::wgpu::BufferBinding<'a>"),
        "{lib_host}"
    );
}

#[test]
fn a_struct_named_like_a_builder_is_an_error() {
    let src = r#"
#[shader]
mod m {
    pub struct Group0 { pub x: f32 }
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [Group0];
    #[compute(workgroup_size(1))]
    fn main() { OUT[0].x = 1.0; }
}
"#;
    let c = codegen::compile_source(src).unwrap_or_else(|e| panic!("{e}"));
    let host =
        codegen::emit::emit(&syn::parse_str::<syn::ItemMod>("mod m {}").unwrap(), &c).to_string();
    assert!(
        host.contains("is the name of the generated builder of bind group 0"),
        "{host}"
    );
}
