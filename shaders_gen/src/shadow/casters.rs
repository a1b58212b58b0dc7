//! Depth-only drawing of shadow casters into atlas regions, and the region copy and clear of
//! the static cache.

/// Draws a caster into one atlas region: the region's view is `VIEWS[instance_index]` (the
/// pass draws instance `v..v + 1` for view `v`, so one bind group serves every region), the
/// mesh transform is the draw's `Draw` (the `view` library's, shared with pre-Z and forward).
/// Depth only, reversed Z; the pipeline adds slope-scaled bias.
#[shader_dsl::shader(uses(crate::shared::view))]
pub mod shadow_caster {
    /// A region's projection.
    pub struct CasterView {
        /// World → clip, reversed Z.
        pub clip_from_world: Mat4,
    }

    #[storage(group = 0, binding = 0)]
    static VIEWS: [CasterView];
    #[uniform(group = 1, binding = 0)]
    static DRAW: Draw;

    #[vertex]
    pub fn vs_caster(#[location(0)] position: Vec3, #[builtin(instance_index)] view: u32) -> Vec4 {
        clip_position(VIEWS[view].clip_from_world, DRAW.world_from_mesh, position)
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
