#[shader_dsl::library(axes(wide: bool = [false, true]))]
pub mod helpers {
    pub fn width() -> u32 {
        select(wide, 8u32, 4u32)
    }
}

#[shader_dsl::shader(axes(msaa: u32 = [1, 4]), uses(crate::helpers))]
mod m {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [u32];
    #[compute(workgroup_size(1))]
    fn main() {
        OUT[0] = width() * msaa;
    }
}
fn main() {}
