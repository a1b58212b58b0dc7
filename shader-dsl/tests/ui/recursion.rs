#[shader_dsl::shader]
mod m {
    fn fact(n: u32) -> u32 {
        if n == 0u32 {
            return 1u32;
        }
        n * fact(n - 1u32)
    }
    #[compute(workgroup_size(1))]
    fn main() {
        let _ = fact(5u32);
    }
}
fn main() {}
