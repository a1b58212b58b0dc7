#[shader_dsl::library(uses(crate::second))]
pub mod first {
    pub fn one() -> u32 {
        two() + 1u32
    }
}

#[shader_dsl::library(uses(crate::first))]
pub mod second {
    pub fn two() -> u32 {
        2u32
    }
}

#[shader_dsl::shader(uses(crate::first))]
mod m {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [u32];
    #[compute(workgroup_size(1))]
    fn main() {
        OUT[0] = one();
    }
}
fn main() {}
