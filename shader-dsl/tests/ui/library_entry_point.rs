#[shader_dsl::library]
pub mod helpers {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [u32];
    #[compute(workgroup_size(1))]
    pub fn main() {
        OUT[0] = 1u32;
    }
}
fn main() {}
