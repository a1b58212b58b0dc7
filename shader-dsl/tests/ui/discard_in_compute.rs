#[shader_dsl::shader]
mod m {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [u32];

    #[compute(workgroup_size(64))]
    fn main(#[builtin(global_invocation_id)] id: UVec3) {
        if id.x > 10u32 {
            discard();
        }
        OUT[id.x] = 1u32;
    }
}
fn main() {}
