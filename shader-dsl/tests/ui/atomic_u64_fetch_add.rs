#[shader_dsl::shader]
mod m {
    #[storage(group = 0, binding = 0, read_write)]
    static VIS64: [Atomic<u64>];
    #[compute(workgroup_size(64))]
    fn main(#[builtin(global_invocation_id)] gid: UVec3) {
        let packed: u64 = ((gid.y as u64) << 32u32) | (gid.x as u64);
        VIS64[gid.x].fetch_min(packed);
        let previous = VIS64[gid.x].fetch_add(1u64);
    }
}
fn main() {}
