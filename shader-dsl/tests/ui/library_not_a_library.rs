pub mod helpers {
    pub const LIMIT: u32 = 16;
}

#[shader_dsl::shader(uses(crate::helpers))]
mod m {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [u32];
    #[compute(workgroup_size(1))]
    fn main() {
        OUT[0] = LIMIT;
    }
}
fn main() {}
