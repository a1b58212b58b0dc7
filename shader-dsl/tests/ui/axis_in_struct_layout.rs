#[shader_dsl::shader(axes(tile: u32 = [8, 16]))]
mod m {
    pub struct Tile {
        pub depths: [f32; tile],
    }
    #[storage(group = 0, binding = 0)]
    static TILES: [Tile];
    #[compute(workgroup_size(1))]
    fn main() {}
}
fn main() {}
