// The front end accepts derivatives anywhere; naga rejects them outside fragment shaders, and
// the error is mapped back through the source map to the call.
#[shader_dsl::shader]
mod m {
    #[storage(group = 0, binding = 0, read_write)]
    static DATA: [f32];
    #[compute(workgroup_size(64))]
    fn main(#[builtin(global_invocation_id)] gid: UVec3) {
        let x = DATA[gid.x];
        DATA[gid.x] = dpdx(x);
    }
}
fn main() {}
