#[shader_dsl::shader]
mod m {
    fn sum(values: Vec<f32>) -> f32 {
        0.0
    }
    #[compute(workgroup_size(1))]
    fn main() {}
}
fn main() {}
