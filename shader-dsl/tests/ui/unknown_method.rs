#[shader_dsl::shader]
mod m {
    #[compute(workgroup_size(1))]
    fn main() {
        let v = Vec3::ONE;
        let n = v.frobnicate();
    }
}
fn main() {}
