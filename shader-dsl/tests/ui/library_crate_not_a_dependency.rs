// A library of a crate this crate does not depend on: the crate name does not resolve.
#[shader_dsl::shader(uses(engine_shaders::lighting))]
mod m {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [u32];
    #[compute(workgroup_size(1))]
    fn main() {
        OUT[0] = 1u32;
    }
}
fn main() {}
