#[shader_dsl::shader]
mod m {
    #[compute(workgroup_size(1))]
    fn main(#[builtin(pixel_id)] id: u32) {}
}
fn main() {}
