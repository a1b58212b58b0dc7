#[shader_dsl::shader]
mod m {
    #[compute(workgroup_size(1))]
    fn main() {
        let x = 1.0;
        let r = &x;
    }
}
fn main() {}
