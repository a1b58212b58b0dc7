//! The module page on a small compiled module: axes, variants, bindings, struct offsets.

use super::{Validation, module_page};

#[test]
fn a_page_lists_axes_variants_bindings_and_struct_offsets() {
    let src = "
        #[shader(axes(tile: u32 = [8, 16] => \"t\"))]
        /// Sums things.
        mod sums {
            pub struct Params { pub count: u32, pub scale: Vec3, pub bias: f32 }
            #[uniform(group = 0, binding = 0)]
            static PARAMS: Params;
            #[storage(group = 0, binding = 1, read_write)]
            static OUT: [u32];
            #[compute(workgroup_size(tile, 1, 1))]
            fn main(#[builtin(global_invocation_id)] id: UVec3) { OUT[id.x] = PARAMS.count; }
        }";
    let file = syn::parse_file(src).expect("parses");
    let (_, item) = codegen::shader_modules(&file).remove(0);
    let compiled = codegen::compile_source(src).expect("compiles");
    let ok = || Validation {
        spirv_val: "ok",
        message: None,
    };
    let page = module_page(&compiled, &item, false, &[ok(), ok()]);
    for needed in [
        "# `sums` (shader module)",
        "Sums things.",
        "| `tile` | `u32` | 8, 16 | `t` |",
        "`main` compute 8×1×1",
        "`main` compute 16×1×1",
        "| 0 | 0 | `PARAMS` | `Group0.params` | `Params` | uniform buffer | compute | all |",
        "| 0 | 1 | `OUT` | `Group0.out` | `[u32]` | storage buffer, read-write | compute | all |",
        "### `Params`",
        "| `count` | `u32` | 0 | 4 |",
        "| `scale` | `Vec3` | 16 | 12 |",
        "| `bias` | `f32` | 28 | 4 |",
    ] {
        assert!(page.contains(needed), "missing `{needed}` in:\n{page}");
    }
    assert!(!page.contains("disagrees"), "{page}");
}
