#[shader_dsl::shader]
mod m {
    fn scale<T>(x: f32) -> f32 {
        x
    }
    #[compute(workgroup_size(1))]
    fn main() {}
}
fn main() {}
