// Golden: `discard()` in a fragment entry point and in a helper it calls (alpha-masked
// materials), with an axis that prunes the mask away.
#[shader_dsl::shader(axes(alpha_mask: bool = [false, true] => "mask"))]
pub mod alpha_mask {
    pub struct Material {
        pub base_color: Vec4,
        pub alpha_cutoff: f32,
    }

    pub struct VsOut {
        #[builtin(position)]
        pub clip: Vec4,
        #[location(0)]
        pub uv: Vec2,
    }

    pub struct FsOut {
        #[location(0)]
        pub color: Vec4,
    }

    #[uniform(group = 0, binding = 0)]
    static MATERIAL: Material;
    #[texture(group = 0, binding = 1)]
    static BASE_COLOR: Texture2d<f32>;
    #[sampler(group = 0, binding = 2)]
    static LINEAR: Sampler;

    /// Discards texels below the material's cutoff.
    fn clip_alpha(alpha: f32) {
        if alpha < MATERIAL.alpha_cutoff {
            discard();
        }
    }

    #[vertex]
    pub fn vs(#[location(0)] position: Vec3, #[location(1)] uv: Vec2) -> VsOut {
        VsOut { clip: Vec4::new(position.x, position.y, position.z, 1.0), uv }
    }

    #[fragment]
    pub fn fs(input: VsOut) -> FsOut {
        let color = BASE_COLOR.sample(LINEAR, input.uv) * MATERIAL.base_color;
        if alpha_mask {
            clip_alpha(color.w);
        }
        if color.w <= 0.0 {
            discard();
        }
        FsOut { color }
    }
}
