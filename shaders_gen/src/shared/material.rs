//! Where a material's textures are read: each texture reference's UV set and
//! `KHR_texture_transform`, and the alpha-mask record of the passes that only cut out.

/// `UvMap`: a texture reference's UV set and transform, and `map_uv`, which applies it; the
/// forward, G-buffer, masked pre-Z and masked shadow-caster shaders read every texture through
/// it. `MaskMaterial` is what the masked depth-only passes (pre-Z and shadow casters) need of a
/// material: one layout, so one bind group serves both.
#[shader_dsl::library]
pub mod material_uv {
    /// One texture reference's coordinates: `uv' = (row_u · (u, v, 1), row_v · (u, v, 1))`,
    /// the first two rows of the `KHR_texture_transform` matrix, over `TEXCOORD_<uv_set>`.
    pub struct UvMap {
        pub row_u: Vec3,
        /// 0: `TEXCOORD_0`, 1: `TEXCOORD_1`.
        pub uv_set: u32,
        pub row_v: Vec3,
    }

    /// The alpha mask of a material: base colour factor, the base colour texture's coordinates,
    /// and the cutoff below which texels leave no depth.
    pub struct MaskMaterial {
        pub base_color: Vec4,
        pub base_color_uv: UvMap,
        pub alpha_cutoff: f32,
    }

    /// The texture coordinates of `map` at a point with UV sets `uv0` and `uv1`.
    pub fn map_uv(map: UvMap, uv0: Vec2, uv1: Vec2) -> Vec2 {
        let uv = select(map.uv_set == 1u32, uv1, uv0).extend(1.0);
        Vec2::new(map.row_u.dot(uv), map.row_v.dot(uv))
    }
}
