#[shader_dsl::shader]
mod m {
    #[storage(group = 0, binding = 0)]
    static DATA: [f32];
    #[compute(workgroup_size(64))]
    fn main(#[builtin(global_invocation_id)] gid: UVec3) {
        DATA[gid.x] = 0.0;
    }
}
fn main() {}
