//! The shadow-atlas debug view.

/// Full-screen debug view of the shadow atlas: the atlas, square and letterboxed in the target,
/// its depth as grey (`sqrt` of the reversed-Z depth: near casters white, nothing black), and
/// each region outlined one target pixel wide in a colour of its light (a hash of the light's
/// id). `REGIONS[i]` is `(x, y, side, light)` in atlas texels. The colours are written as they
/// are: draw into a `*Unorm` target to get them as bytes.
#[shader_dsl::shader()]
pub mod shadow_atlas_view {
    pub struct AtlasViewParams {
        /// Target size in pixels.
        pub screen: UVec2,
        /// Atlas side in texels.
        pub atlas: u32,
        /// Regions in `REGIONS`.
        pub region_count: u32,
    }

    #[uniform(group = 0, binding = 0)]
    static PARAMS: AtlasViewParams;
    #[texture(group = 0, binding = 1)]
    static ATLAS: TextureDepth2d;
    #[storage(group = 0, binding = 2)]
    static REGIONS: [UVec4];

    #[vertex]
    pub fn vs_fullscreen(#[builtin(vertex_index)] index: u32) -> Vec4 {
        let uv = Vec2::new(((index << 1u32) & 2u32) as f32, (index & 2u32) as f32);
        Vec4::new(uv.x * 2.0 - 1.0, uv.y * 2.0 - 1.0, 0.0, 1.0)
    }

    /// A bright colour for `light`.
    fn light_colour(light: u32) -> Vec3 {
        let h = (light * 2_654_435_761u32) >> 8u32;
        let c = Vec3::new(
            (h & 255u32) as f32,
            ((h >> 8u32) & 255u32) as f32,
            ((h >> 16u32) & 255u32) as f32,
        );
        c / 255.0 * 0.6 + 0.4
    }

    #[fragment]
    pub fn fs_atlas(#[builtin(position)] position: Vec4) -> Vec4 {
        let side = PARAMS.screen.x.min(PARAMS.screen.y);
        let origin = (PARAMS.screen - UVec2::splat(side)) / 2u32;
        let px = position.xy().floor().as_uvec2();
        let mut colour = Vec3::new(0.05, 0.05, 0.12);
        if px.x >= origin.x && px.y >= origin.y && px.x < origin.x + side && px.y < origin.y + side
        {
            let scale = PARAMS.atlas as f32 / side as f32;
            let texel = ((px - origin).as_vec2() * scale).as_uvec2();
            let depth = ATLAS.load(texel, 0u32);
            colour = Vec3::splat(depth.max(0.0).sqrt());
            let line = scale.max(1.0) as u32;
            for i in 0u32..PARAMS.region_count {
                let r = REGIONS[i];
                let inside =
                    texel.x >= r.x && texel.y >= r.y && texel.x < r.x + r.z && texel.y < r.y + r.z;
                let border = texel.x < r.x + line
                    || texel.y < r.y + line
                    || texel.x + line >= r.x + r.z
                    || texel.y + line >= r.y + r.z;
                if inside && border {
                    colour = light_colour(r.w);
                }
            }
        }
        colour.extend(1.0)
    }
}
