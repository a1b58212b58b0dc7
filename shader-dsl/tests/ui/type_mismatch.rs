#[shader_dsl::shader]
mod m {
    #[compute(workgroup_size(1))]
    fn main() {
        let count = 3u32;
        let scaled: f32 = count * 2.0;
    }
}
fn main() {}
