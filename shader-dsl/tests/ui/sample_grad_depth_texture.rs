#[shader_dsl::shader]
mod m {
    #[texture(group = 0, binding = 0)]
    static SHADOW: TextureDepth2d;
    #[sampler(group = 0, binding = 1)]
    static LINEAR: Sampler;
    #[fragment]
    fn fs(#[location(0)] uv: Vec2) -> Vec4 {
        let d = SHADOW.sample_grad(LINEAR, uv, dpdx(uv), dpdy(uv));
        Vec4::splat(d)
    }
}
fn main() {}
