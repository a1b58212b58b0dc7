#[shader_dsl::shader(axes(tile: u32 = [8, 16]), exclude(tiles == 8))]
mod m {
    #[compute(workgroup_size(tile))]
    fn main() {}
}
fn main() {}
