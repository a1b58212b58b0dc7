//! Material textures reached by index, without bindless: every mip level of every material
//! texture is its own rectangle in the layers of one 2D array texture (the material atlas),
//! with a one-texel border, and the shader does what a sampler would: wrap, level choice and
//! texel filter.

/// `atlas_sample`: one material texture of the atlas, sampled as a glTF sampler would sample
/// it on its own.
///
/// Each level is stored at its own rectangle, surrounded by a one-texel border holding the
/// texels the wrap mode puts beside the edge (the opposite edge for repeat, the edge itself for
/// mirrored repeat and clamp). The shader wraps the coordinates first, then samples a level's
/// rectangle with a bilinear, clamping sampler: the footprint of a bilinear tap reaches at
/// most the border, so no level and no neighbour ever bleeds in, at any distance. Levels are
/// chosen from the coordinates' screen derivatives as Vulkan chooses them (`λ = log2 ρ`, `ρ`
/// the longer of the two derivatives in texels of level 0; magnification where `λ ≤ 0`;
/// nearest mipmapping at `⌈λ + ½⌉ − 1`, linear between `⌊λ⌋` and the next). Nearest texel
/// filtering samples the texel's centre. The caller passes the derivatives, so it may sample
/// in non-uniform control flow, or in compute with analytic derivatives.
#[shader_dsl::library]
pub mod material_atlas {
    /// One material texture: an image with one sampler's wrap and filter modes.
    pub struct AtlasTexture {
        /// Size of level 0 in texels.
        pub size: Vec2,
        /// Index of level 0 in `ATLAS_LEVELS`; the levels follow it.
        pub first_level: u32,
        pub levels: u32,
        /// Wrap of `u` (bits 0–1) and `v` (bits 2–3): `WRAP_REPEAT`, `WRAP_MIRROR`, `WRAP_CLAMP`.
        pub wrap: u32,
        /// `FILTER_MAG_NEAREST`, `FILTER_MIN_NEAREST`, and the mipmap mode at `FILTER_MIP_SHIFT`
        /// (`MIP_NONE`, `MIP_NEAREST`, `MIP_LINEAR`).
        pub filters: u32,
    }

    /// One mip level's rectangle (inside its border) in the atlas.
    pub struct AtlasLevel {
        /// Corner of texel (0, 0), in atlas UV.
        pub origin: Vec2,
        /// Size of the level in atlas UV.
        pub extent: Vec2,
        /// Size of the level in texels.
        pub size: Vec2,
        /// The atlas layer.
        pub layer: u32,
        pub pad: u32,
    }

    pub const WRAP_REPEAT: u32 = 0;
    pub const WRAP_MIRROR: u32 = 1;
    pub const WRAP_CLAMP: u32 = 2;
    pub const FILTER_MAG_NEAREST: u32 = 1;
    pub const FILTER_MIN_NEAREST: u32 = 2;
    pub const FILTER_MIP_SHIFT: u32 = 2;
    pub const MIP_NONE: u32 = 0;
    pub const MIP_NEAREST: u32 = 1;
    pub const MIP_LINEAR: u32 = 2;

    #[storage(group = 2, binding = 1)]
    static ATLAS_TEXTURES: [AtlasTexture];
    #[storage(group = 2, binding = 2)]
    static ATLAS_LEVELS: [AtlasLevel];
    /// The atlas as sRGB colour (decoded to linear before filtering).
    #[texture(group = 2, binding = 3)]
    static ATLAS_COLOUR: Texture2dArray<f32>;
    /// The same texels as stored (normals, metallic-roughness, occlusion).
    #[texture(group = 2, binding = 4)]
    static ATLAS_DATA: Texture2dArray<f32>;
    /// Bilinear, clamping, one level.
    #[sampler(group = 2, binding = 5)]
    static ATLAS_SAMPLER: Sampler;

    /// `x` wrapped into `[0, 1]` by `mode`.
    pub fn wrap_coordinate(x: f32, mode: u32) -> f32 {
        let mut out = x - x.floor();
        if mode == WRAP_MIRROR {
            let period = x - 2.0 * (x * 0.5).floor();
            out = select(period > 1.0, 2.0 - period, period);
        } else if mode == WRAP_CLAMP {
            out = x.saturate();
        }
        out
    }

    /// Level `level` at wrapped coordinates `uv`, filtered bilinearly or (`nearest`) at the
    /// centre of the texel `uv` falls in.
    pub fn atlas_level_texel(level: u32, uv: Vec2, nearest: bool, colour: bool) -> Vec4 {
        let l = ATLAS_LEVELS[level];
        let mut at = uv;
        if nearest {
            let texel = (uv * l.size).floor().clamp(Vec2::ZERO, l.size - 1.0);
            at = (texel + 0.5) / l.size;
        }
        let p = l.origin + at * l.extent;
        // One tap, through the view the texture's kind needs.
        let mut texel = Vec4::ZERO;
        if colour {
            texel = ATLAS_COLOUR.sample_level(ATLAS_SAMPLER, p, l.layer, 0.0);
        } else {
            texel = ATLAS_DATA.sample_level(ATLAS_SAMPLER, p, l.layer, 0.0);
        }
        texel
    }

    /// Material texture `index` at `uv`, whose screen derivatives are `ddx` and `ddy`;
    /// `colour`: an sRGB colour texture (base colour, emissive), filtered in linear light.
    pub fn atlas_sample(index: u32, colour: bool, uv: Vec2, ddx: Vec2, ddy: Vec2) -> Vec4 {
        let t = ATLAS_TEXTURES[index];
        let dx = ddx * t.size;
        let dy = ddy * t.size;
        let lod = 0.5 * dx.dot(dx).max(dy.dot(dy)).log2();
        let magnified = !(lod > 0.0);
        let mip = t.filters >> FILTER_MIP_SHIFT;
        let last = (t.levels - 1u32) as f32;
        let mut level = 0.0;
        if !magnified && mip == MIP_NEAREST {
            level = ((lod + 0.5).ceil() - 1.0).clamp(0.0, last);
        } else if !magnified && mip == MIP_LINEAR {
            level = lod.clamp(0.0, last);
        }
        let nearest = select(
            magnified,
            (t.filters & FILTER_MAG_NEAREST) != 0u32,
            (t.filters & FILTER_MIN_NEAREST) != 0u32,
        );
        let wrapped = Vec2::new(
            wrap_coordinate(uv.x, t.wrap & 3u32),
            wrap_coordinate(uv.y, (t.wrap >> 2u32) & 3u32),
        );
        let below = level.floor();
        let first = t.first_level + below as u32;
        let mut texel = atlas_level_texel(first, wrapped, nearest, colour);
        let blend = level - below;
        if blend > 0.0 {
            let next = atlas_level_texel(first + 1u32, wrapped, nearest, colour);
            texel = texel.lerp(next, blend);
        }
        texel
    }
}
