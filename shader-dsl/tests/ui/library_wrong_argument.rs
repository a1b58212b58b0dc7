#[shader_dsl::library]
pub mod helpers {
    pub fn twice(x: f32) -> f32 {
        x * 2.0
    }
}

#[shader_dsl::shader(uses(crate::helpers))]
mod m {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [f32];
    #[compute(workgroup_size(1))]
    fn main(#[builtin(global_invocation_id)] gid: UVec3) {
        OUT[gid.x] = twice(gid.x);
    }
}
fn main() {}
