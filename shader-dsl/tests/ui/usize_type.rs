#[shader_dsl::shader]
mod m {
    #[compute(workgroup_size(1))]
    fn main() {
        let i: usize = 0;
    }
}
fn main() {}
