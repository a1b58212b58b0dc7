#[shader_dsl::shader(axes(scalarize: bool = [false, true]), requires(subgroup = scalarize))]
mod m {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [u32];
    #[compute(workgroup_size(64))]
    fn main(#[builtin(global_invocation_id)] gid: UVec3) {
        let total = subgroup_add(1u32);
        OUT[gid.x] = total;
    }
}
fn main() {}
