//! Depth-only drawing of shadow casters into atlas regions, and the region copy and clear of
//! the static cache.

/// Draws a caster into one atlas region: the instance index selects a `Cast` record of `CASTS`
/// (the pass draws instance `c..c + 1` for cast `c`), which names the draw (its record in the
/// `view` library's `DRAWS`, shared with pre-Z and forward) and the region's view in `VIEWS`, so
/// one bind group serves every region and every caster.
/// Depth only, reversed Z; the pipeline adds slope-scaled bias.
///
/// Alpha-masked materials (`alpha_mask`) cut out: `vs_caster_mask` passes both UV sets and the
/// vertex colour's alpha to `fs_caster_mask`, which discards texels below the cutoff exactly as
/// the masked pre-Z does (group 2 is the scene's one material group, `material_table`). Opaque casters have no
/// fragment stage.
#[shader_dsl::shader(
    axes(alpha_mask: bool = [false, true] => "mask"),
    uses(crate::shared::view, crate::shared::material_uv, crate::shared::material_table),
)]
pub mod shadow_caster {
    /// A region's projection.
    pub struct CasterView {
        /// World → clip, reversed Z.
        pub clip_from_world: Mat4,
    }

    /// One caster drawn into one region.
    pub struct Cast {
        /// The draw: its index in `DRAWS`.
        pub draw: u32,
        /// The region: its index in `VIEWS`.
        pub view: u32,
    }

    #[storage(group = 0, binding = 0)]
    static VIEWS: [CasterView];
    #[storage(group = 0, binding = 1)]
    static CASTS: [Cast];

    #[vertex]
    pub fn vs_caster(
        #[location(0)] position: Vec3,
        #[builtin(instance_index)] cast_index: u32,
    ) -> Vec4 {
        cast_position(CASTS[cast_index], position)
    }

    /// Masked casters' vertices: position, `TEXCOORD_0`, `TEXCOORD_1` and `COLOR_0`.
    #[vertex]
    pub fn vs_caster_mask(
        #[location(0)] position: Vec3,
        #[location(1)] uv0: Vec2,
        #[location(2)] uv1: Vec2,
        #[location(3)] color: Vec4,
        #[builtin(instance_index)] cast_index: u32,
    ) -> MaskVsOut {
        MaskVsOut {
            clip: cast_position(CASTS[cast_index], position),
            uv0,
            uv1,
            color_alpha: color.w,
            material: DRAWS[CASTS[cast_index].draw].material,
        }
    }

    /// Clip position of a mesh-space position of `record`'s draw in its region's view.
    fn cast_position(record: Cast, position: Vec3) -> Vec4 {
        clip_position(
            VIEWS[record.view].clip_from_world,
            DRAWS[record.draw].world_from_mesh,
            position,
        )
    }

    /// Masked casters: texels below the cutoff leave no depth in the atlas.
    #[fragment]
    pub fn fs_caster_mask(input: MaskVsOut) {
        if alpha_mask && mask_cuts(input) {
            discard();
        }
    }
}

/// Region composition: `vs_region` covers the viewport (the region) with one triangle at
/// depth 0 (the far plane, reversed Z), which clears the region when drawn with `Always`;
/// `fs_copy_static` writes the static cache's depth at the same texel (the atlases are the same
/// size), which copies a region: WebGPU copies whole depth subresources only.
#[shader_dsl::shader()]
pub mod shadow_compose {
    /// The copied depth.
    pub struct DepthOut {
        #[builtin(frag_depth)]
        pub depth: f32,
    }

    #[texture(group = 0, binding = 0)]
    static STATIC_ATLAS: TextureDepth2d;

    #[vertex]
    pub fn vs_region(#[builtin(vertex_index)] index: u32) -> Vec4 {
        let uv = Vec2::new(((index << 1u32) & 2u32) as f32, (index & 2u32) as f32);
        Vec4::new(uv.x * 2.0 - 1.0, uv.y * 2.0 - 1.0, 0.0, 1.0)
    }

    #[fragment]
    pub fn fs_copy_static(#[builtin(position)] position: Vec4) -> DepthOut {
        DepthOut {
            depth: STATIC_ATLAS.load(position.xy().floor().as_uvec2(), 0u32),
        }
    }
}
