//! The resolved HDR image of deferred shading written into every sample of a multisampled
//! target, so blended surfaces and particles can be drawn over it with MSAA.

/// Full-screen pass: each fragment loads its pixel of `HDR` and writes it to every sample
/// (the colour of a pixel's samples is their resolved mean from then on; blending over a
/// uniform pixel and resolving equals resolving and blending).
#[shader_dsl::shader]
pub mod hdr_expand {
    #[texture(group = 0, binding = 0, unfilterable)]
    static HDR: Texture2d<f32>;

    #[vertex]
    pub fn vs_fullscreen(#[builtin(vertex_index)] index: u32) -> Vec4 {
        let uv = Vec2::new(((index << 1u32) & 2u32) as f32, (index & 2u32) as f32);
        Vec4::new(uv.x * 2.0 - 1.0, uv.y * 2.0 - 1.0, 0.0, 1.0)
    }

    #[fragment]
    pub fn fs_expand(#[builtin(position)] position: Vec4) -> Vec4 {
        HDR.load(position.xy().floor().as_uvec2(), 0u32)
    }
}
