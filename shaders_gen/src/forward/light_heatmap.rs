//! The light-count and decal-count heatmap debug view.

/// Full-screen debug view: each pixel is coloured by the number of lights (or, with `section`
/// set to the grid's decal section, decals) in its tile's or froxel's list
/// (`GRID[section + cell].y`, the lists `tile_cull`/`cluster_cull` write, bound as the
/// `light_lists` library declares them), on a ramp black
/// → blue → green → yellow → red with stops at counts 0, ¼, ½, ¾ and 1 × `max_count`
/// (saturating). The bottom 16 pixel rows are the legend: the same ramp from left (0) to right
/// (`max_count`).
///
/// `list` 1: tiled (cell from `tile_size`/`tiles`, the opaque list); `list` 2: clustered, whose
/// depth slice comes
/// from sample 0 of the depth buffer through `inv_projection` and `light_grid`'s `slice_of`
/// (the cell lookups are the `light_grid` library's, like the culling kernels' and `forward`'s);
/// sky pixels (depth 1) show 0. The colours are written as they are: draw into a `*Unorm`
/// target to get them as bytes.
#[shader_dsl::shader(
    axes(list: u32 = [1, 2] => "list", msaa: u32 = [1, 2, 4, 8]),
    exclude(list == 1 && msaa > 1),
    uses(crate::shared::light_grid, crate::shared::light_lists),
)]
pub mod heatmap {
    pub struct HeatmapParams {
        pub inv_projection: Mat4,
        /// Target size in pixels.
        pub screen: UVec2,
        /// Tiles across and down.
        pub tiles: UVec2,
        /// Tile size in pixels.
        pub tile_size: u32,
        /// Depth slices (clustered).
        pub slices: u32,
        pub near: f32,
        pub far: f32,
        /// Count shown as full red.
        pub max_count: u32,
        /// Grid entries before the lists shown: 0 for lights, the decal section for decals.
        pub section: u32,
    }

    /// Rows of the legend strip at the bottom.
    pub const LEGEND_ROWS: u32 = 16;

    #[uniform(group = 0, binding = 0)]
    static PARAMS: HeatmapParams;
    #[texture(group = 0, binding = 5)]
    #[when(list == 2 && msaa == 1)]
    static DEPTH: TextureDepth2d;
    #[texture(group = 0, binding = 5)]
    #[when(list == 2 && msaa > 1)]
    static DEPTH_MS: TextureDepthMultisampled2d;

    #[vertex]
    pub fn vs_fullscreen(#[builtin(vertex_index)] index: u32) -> Vec4 {
        let uv = Vec2::new(((index << 1u32) & 2u32) as f32, (index & 2u32) as f32);
        Vec4::new(uv.x * 2.0 - 1.0, uv.y * 2.0 - 1.0, 0.0, 1.0)
    }

    /// The ramp colour at `t` in [0, 1].
    fn ramp(t: f32) -> Vec3 {
        let s = t.saturate() * 4.0;
        let mut c = Vec3::ZERO.lerp(Vec3::Z, s);
        if s > 1.0 {
            c = Vec3::Z.lerp(Vec3::Y, s - 1.0);
        }
        if s > 2.0 {
            c = Vec3::Y.lerp(Vec3::new(1.0, 1.0, 0.0), s - 2.0);
        }
        if s > 3.0 {
            c = Vec3::new(1.0, 1.0, 0.0).lerp(Vec3::X, s - 3.0);
        }
        c
    }

    #[fragment]
    pub fn fs_heatmap(#[builtin(position)] position: Vec4) -> Vec4 {
        let px = position.xy().floor().as_uvec2();
        let max_count = PARAMS.max_count.max(1u32) as f32;
        if px.y + LEGEND_ROWS >= PARAMS.screen.y {
            let t = px.x as f32 / (PARAMS.screen.x - 1u32).max(1u32) as f32;
            return ramp(t).extend(1.0);
        }
        let mut count = 0u32;
        if list == 1 {
            count = GRID[PARAMS.section + tile_cell(px, PARAMS.tile_size, PARAMS.tiles.x)].y;
        } else {
            let mut d = 1.0;
            if msaa == 1 {
                d = DEPTH.load(px, 0u32);
            } else {
                d = DEPTH_MS.load(px, 0u32);
            }
            if d < 1.0 {
                let depth = view_depth(PARAMS.inv_projection, d);
                let slice = slice_of(depth, PARAMS.near, PARAMS.far, PARAMS.slices);
                count =
                    GRID[PARAMS.section + froxel_cell(px, slice, PARAMS.tile_size, PARAMS.tiles)].y;
            }
        }
        if INDICES.len() == 0u32 {
            count = 0u32;
        }
        ramp(count as f32 / max_count).extend(1.0)
    }
}
