//! Where a material's textures are read (each texture reference's UV set and
//! `KHR_texture_transform`), and every material of a scene in one buffer.

/// `UvMap`: a texture reference's UV set and transform, and `map_uv`, which applies it; the
/// forward, G-buffer, masked pre-Z and masked shadow-caster shaders read every texture through
/// it (by `material_table`).
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

    /// The texture coordinates of `map` at a point with UV sets `uv0` and `uv1`.
    pub fn map_uv(map: UvMap, uv0: Vec2, uv1: Vec2) -> Vec2 {
        let uv = select(map.uv_set == 1u32, uv1, uv0).extend(1.0);
        Vec2::new(map.row_u.dot(uv), map.row_v.dot(uv))
    }
}

/// Every material of a scene in one storage buffer (`MATERIALS`, group 2 binding 0), its
/// textures reached by index through the material atlas: a draw's record names its material,
/// so one bind group serves every draw and one multi-draw every pipeline.
///
/// `GpuMaterial` holds the glTF metallic-roughness factors, each multiplying its texture, and
/// where each texture is read (`UvMap`: UV set and `KHR_texture_transform`; an atlas texture
/// index, `NO_TEXTURE` where the material has none). `material_texel` reads one texture with
/// the derivatives of its coordinates, so it may run in any control flow (and in compute with
/// analytic derivatives); `uv_derivatives` takes them in a fragment shader's uniform control
/// flow.
#[shader_dsl::library(uses(crate::shared::material_uv, crate::shared::material_atlas))]
pub mod material_table {
    pub struct GpuMaterial {
        pub base_color: Vec4,
        pub emissive: Vec3,
        pub metallic: f32,
        pub roughness: f32,
        pub normal_scale: f32,
        pub occlusion_strength: f32,
        /// Positive for alpha-masked materials: texels below it are discarded.
        pub alpha_cutoff: f32,
        pub base_color_uv: UvMap,
        pub normal_uv: UvMap,
        pub metallic_roughness_uv: UvMap,
        pub occlusion_uv: UvMap,
        pub emissive_uv: UvMap,
        /// Atlas texture indices (`NO_TEXTURE`: none).
        pub base_color_texture: u32,
        pub normal_texture: u32,
        pub metallic_roughness_texture: u32,
        pub occlusion_texture: u32,
        pub emissive_texture: u32,
        /// 1 where both faces are drawn (glTF `doubleSided`), else 0. The blended forward
        /// pipeline culls no face and reads it to drop back faces itself.
        pub double_sided: u32,
        /// Where a material written in the DSL (`#[shader_dsl::material]` with a parameter
        /// struct) finds its parameters: an index into its program's `PARAMS` (0 otherwise).
        pub params: u32,
        /// The material program that shades it: 0 for glTF PBR, else the program's id
        /// (`MaterialProgram::id` on the host). The visibility path's kernels, one a program,
        /// each shade the triangles of their own program by it.
        pub program: u32,
    }

    /// A point's two UV sets and their screen derivatives.
    pub struct UvDerivatives {
        pub uv0: Vec2,
        pub uv1: Vec2,
        pub uv0_dx: Vec2,
        pub uv0_dy: Vec2,
        pub uv1_dx: Vec2,
        pub uv1_dy: Vec2,
    }

    /// An alpha-masked depth-only fragment's inputs, the masked vertex output of pre-Z and of the
    /// shadow casters: clip position (invariant, so pre-Z depth equals the lit pass's), both UV
    /// sets, the vertex colour's alpha and the draw's material (`MATERIALS` index).
    pub struct MaskVsOut {
        #[builtin(position)]
        #[invariant]
        pub clip: Vec4,
        #[location(0)]
        pub uv0: Vec2,
        #[location(1)]
        pub uv1: Vec2,
        #[location(2)]
        pub color_alpha: f32,
        #[location(3)]
        #[interpolate(flat)]
        pub material: u32,
    }

    /// A material texture slot without a texture.
    pub const NO_TEXTURE: u32 = 4294967295u32;

    #[storage(group = 2, binding = 0)]
    static MATERIALS: [GpuMaterial];

    /// `uv0` and `uv1` with their screen derivatives (fragment shaders, uniform control flow).
    pub fn uv_derivatives(uv0: Vec2, uv1: Vec2) -> UvDerivatives {
        UvDerivatives {
            uv0,
            uv1,
            uv0_dx: dpdx(uv0),
            uv0_dy: dpdy(uv0),
            uv1_dx: dpdx(uv1),
            uv1_dy: dpdy(uv1),
        }
    }

    /// Atlas texture `texture` read through `map` (`colour`: sRGB colour), or `absent` where
    /// the slot has no texture.
    pub fn material_texel(
        texture: u32,
        colour: bool,
        map: UvMap,
        d: UvDerivatives,
        absent: Vec4,
    ) -> Vec4 {
        let mut texel = absent;
        if texture != NO_TEXTURE {
            let second = map.uv_set == 1u32;
            let dx = select(second, d.uv1_dx, d.uv0_dx);
            let dy = select(second, d.uv1_dy, d.uv0_dy);
            // The transform's linear part carries the derivatives.
            let ddx = Vec2::new(map.row_u.xy().dot(dx), map.row_v.xy().dot(dx));
            let ddy = Vec2::new(map.row_u.xy().dot(dy), map.row_v.xy().dot(dy));
            texel = atlas_sample(texture, colour, map_uv(map, d.uv0, d.uv1), ddx, ddy);
        }
        texel
    }

    /// Whether the masked fragment `input` is cut by its material's alpha mask (fragment
    /// shaders, uniform control flow: the UV derivatives are taken here).
    pub fn mask_cuts(input: MaskVsOut) -> bool {
        masked_out(
            input.material,
            uv_derivatives(input.uv0, input.uv1),
            input.color_alpha,
        )
    }

    /// The alpha of material `index` at `d` (base colour factor × texture × vertex alpha), and
    /// whether a masked material discards it (below its cutoff).
    pub fn masked_out(index: u32, d: UvDerivatives, vertex_alpha: f32) -> bool {
        let m = MATERIALS[index];
        let texel = material_texel(m.base_color_texture, true, m.base_color_uv, d, Vec4::ONE);
        let alpha = m.base_color.w * texel.w * vertex_alpha;
        m.alpha_cutoff > 0.0 && alpha < m.alpha_cutoff
    }
}
