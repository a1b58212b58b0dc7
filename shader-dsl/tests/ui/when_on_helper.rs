#[shader_dsl::shader(axes(msaa: u32 = [0, 4] => "msaa" unless 0))]
mod m {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [u32];
    #[when(msaa > 0)]
    fn samples() -> u32 {
        msaa
    }
    #[compute(workgroup_size(1))]
    fn main(#[builtin(global_invocation_id)] gid: UVec3) {
        OUT[gid.x] = samples();
    }
}
fn main() {}
