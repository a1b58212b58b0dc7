#[shader_dsl::shader(axes(tile: u32 = [8, 16]))]
mod m {
    #[compute(workgroup_size(tile))]
    fn main() {
        tile = 4u32;
    }
}
fn main() {}
