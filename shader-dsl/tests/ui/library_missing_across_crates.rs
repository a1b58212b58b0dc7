// A library path into another crate (a dependency that exports libraries: `shared::tint`) that
// names no library of that crate: rustc reports the exported macro the path would need
// (`__shader_library_<name>`) as missing, at the path.
#[shader_dsl::shader(uses(dsl_library_crate::shared::no_such_library))]
mod m {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [u32];
    #[compute(workgroup_size(1))]
    fn main() {
        OUT[0] = 1u32;
    }
}
fn main() {}
