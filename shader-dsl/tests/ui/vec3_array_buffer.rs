#[shader_dsl::shader]
mod m {
    #[storage(group = 0, binding = 0)]
    static POSITIONS: [Vec3];
    #[compute(workgroup_size(1))]
    fn main() {
        let p = POSITIONS[0];
    }
}
fn main() {}
