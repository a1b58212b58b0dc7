#[shader_dsl::shader]
mod m {
    #[texture(group = 0, binding = 0)]
    static LAYERS: Texture2dArray<f32>;
    #[sampler(group = 0, binding = 1)]
    static LINEAR: Sampler;
    #[fragment]
    fn fs(#[location(0)] uv: Vec2) -> Vec4 {
        LAYERS.sample_grad(LINEAR, uv, dpdx(uv), dpdy(uv))
    }
}
fn main() {}
