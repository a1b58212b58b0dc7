#[shader_dsl::shader]
mod m {
    #[storage(group = 0, binding = 0)]
    static A: [u32];
    #[storage(group = 0, binding = 0, read_write)]
    static B: [u32];
    #[compute(workgroup_size(1))]
    fn main() {}
}
fn main() {}
