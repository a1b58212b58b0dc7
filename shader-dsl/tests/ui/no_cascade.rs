// The DSL error is the only error: the stub module keeps the host types, constants, key types
// and `m::VARIANTS` resolvable for the code that uses them.
#[shader_dsl::shader(axes(tile: u32 = [8, 16] => "t"))]
mod m {
    pub struct Params {
        pub scale: Vec3,
        pub count: u32,
    }
    pub const LIMIT: u32 = 64;
    #[uniform(group = 0, binding = 0)]
    static PARAMS: Params;
    #[compute(workgroup_size(tile))]
    fn main() {
        let x = undefined_name + PARAMS.scale.x;
    }
}
fn main() {
    let p = m::Params::new(glam::Vec3::ONE, m::LIMIT);
    let key = m::VariantKey { tile: m::Tile::T16 };
    let _ = (p, key.name(), m::VARIANTS.len());
}
