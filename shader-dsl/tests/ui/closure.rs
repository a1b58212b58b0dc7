#[shader_dsl::shader]
mod m {
    #[compute(workgroup_size(1))]
    fn main() {
        let double = |x: f32| x * 2.0;
    }
}
fn main() {}
