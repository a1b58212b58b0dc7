#[shader_dsl::library]
pub mod base {
    pub const LIMIT: u32 = 16;
}

#[shader_dsl::library(uses(crate::base))]
pub mod middle {
    pub fn twice() -> u32 {
        LIMIT * 2u32
    }
}

#[shader_dsl::shader(uses(crate::middle))]
mod m {
    const LIMIT: u32 = 32;
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [u32];
    #[compute(workgroup_size(1))]
    fn main() {
        OUT[0] = twice() + LIMIT;
    }
}
fn main() {}
