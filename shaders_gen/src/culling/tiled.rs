//! Tiled and 2.5D light culling, the fine level: one workgroup per screen tile.

/// Tiled culling (Harada's Forward+, reference 000) and with `depth_mask` the 2.5D variant
/// (Harada 2012), over the candidates `cull_prepare` left for the tile's super-tile.
///
/// Each workgroup reads its tile's depth bounds and 2.5D mask (`TILE_DEPTH`), builds the tile
/// frustum and classifies every candidate into the tile's lists:
/// * list 0, for opaque and alpha-masked surfaces (the pre-Z depth): the frustum bounded by the
///   tile's depth range and, with `depth_mask`, a 2.5D mask sharing a cell with the geometry's;
/// * list 1, only with `transparent`, for blended surfaces (absent from pre-Z): the frustum from
///   the near plane to the tile's farthest opaque sample, or to the far plane when any sample of
///   the tile is sky (`TILE_DEPTH[tile].w`).
///
/// Box items (decals) are tested as boxes: planes against the box's corners, the frustum's
/// bounding box against the box's, the box's depth span against the 2.5D mask.
///
/// Lists are counted, allocated with one atomic per tile and then written (`cull_append`), so
/// no list is ever cut short. Planes and the sphere and box tests are `light_grid`'s.
#[shader_dsl::shader(
    axes(
        tile: u32 = [8, 16, 32] => "t",
        depth_mask: bool = [false, true] => "mask",
    ),
    uses(crate::shared::light_grid, crate::shared::cull_append),
)]
pub mod tile_cull {
    /// Invocations per tile.
    pub const WORKGROUP: u32 = 64;

    /// View depth (distance along −Z) of a depth-buffer value.
    fn depth_to_view(d: f32) -> f32 {
        view_depth(PARAMS.inv_projection, d)
    }

    /// Bits of the cells a sphere spanning view depths `[lo, hi]` covers (0 outside the range).
    fn sphere_mask(lo: f32, hi: f32, near: f32, far: f32) -> u32 {
        let mut mask = 0u32;
        if hi >= near && lo <= far {
            let a = mask_cell(lo, near, far);
            let b = mask_cell(hi, near, far);
            if b - a >= 31u32 {
                mask = 0xffff_ffffu32;
            } else {
                mask = ((1u32 << (b - a + 1u32)) - 1u32) << a;
            }
        }
        mask
    }

    /// The tile's depth information, as `cull_prepare::tile_depth` left it.
    struct TileRange {
        opaque: bool,
        near: f32,
        far: f32,
        mask: u32,
        transparent_near: f32,
        transparent_far: f32,
    }

    /// The lists (bit 0 opaque, bit 1 transparent) of an item that reaches the tile's opaque
    /// frustum (`opaque`) and its transparent one (`transparent`) and spans view depths
    /// `[lo, hi]`: with `depth_mask`, the opaque list also needs a 2.5D cell shared with the
    /// geometry's.
    fn lists_of(opaque: bool, transparent: bool, lo: f32, hi: f32, range: TileRange) -> u32 {
        let mut kept = opaque;
        if depth_mask && kept {
            kept = (sphere_mask(lo, hi, range.near, range.far) & range.mask) != 0u32;
        }
        let mut bits = 0u32;
        if kept {
            bits = 1u32;
        }
        if transparent {
            bits = bits | 2u32;
        }
        bits
    }

    /// The lists the view-space sphere `s` belongs to: its planes test and, with `box_test`, its
    /// distance to the frustum's box.
    fn classify(s: Vec4, sides: SidePlanes, rays: TileRays, range: TileRange) -> u32 {
        let c = s.xyz();
        let r = s.w;
        let near = range.near;
        let far = range.far;
        let tn = range.transparent_near;
        let tf = range.transparent_far;
        let opaque = range.opaque
            && sphere_in_frustum(c, r, sides, near, far)
            && (PARAMS.box_test == 0u32 || sphere_reaches_box(c, r, rays, near, far));
        let transparent = PARAMS.transparent != 0u32
            && sphere_in_frustum(c, r, sides, tn, tf)
            && (PARAMS.box_test == 0u32 || sphere_reaches_box(c, r, rays, tn, tf));
        lists_of(opaque, transparent, -c.z - r, -c.z + r, range)
    }

    /// The lists the view-space box `b` belongs to: the same cells as `classify`, with the box's
    /// planes test, its axis-aligned box against the frustum's box, and its depth span for the
    /// 2.5D mask.
    fn classify_box(b: ViewBox, sides: SidePlanes, rays: TileRays, range: TileRange) -> u32 {
        let c = b.center;
        let e = box_extent(b.x, b.y, b.z);
        let near = range.near;
        let far = range.far;
        let tn = range.transparent_near;
        let tf = range.transparent_far;
        let opaque = range.opaque
            && box_in_frustum(c, b.x, b.y, b.z, sides, near, far)
            && (PARAMS.box_test == 0u32 || box_reaches_box(c, e, rays, near, far));
        let transparent = PARAMS.transparent != 0u32
            && box_in_frustum(c, b.x, b.y, b.z, sides, tn, tf)
            && (PARAMS.box_test == 0u32 || box_reaches_box(c, e, rays, tn, tf));
        lists_of(opaque, transparent, -c.z - e.z, -c.z + e.z, range)
    }

    /// Candidate `i`'s item (`x`) and its lists (`y`): its bounding sphere decides, and a box
    /// item must pass its box's test as well. The item index is loaded only for a hit.
    fn candidate_lists(
        st: u32,
        coarse: bool,
        i: u32,
        sides: SidePlanes,
        rays: TileRays,
        range: TileRange,
    ) -> UVec2 {
        let mut bits = classify(candidate_sphere(st, coarse, i), sides, rays, range);
        let mut item = 0u32;
        if bits != 0u32 {
            item = candidate_item(st, coarse, i);
            if is_box(item) {
                bits = bits & classify_box(view_box(item), sides, rays, range);
            }
        }
        UVec2::new(item, bits)
    }

    #[compute(workgroup_size(64, 1, 1))]
    pub fn cull(#[builtin(local_invocation_index)] lid: u32, #[builtin(workgroup_id)] wg: UVec3) {
        let tile_index = wg.y * PARAMS.tiles.x + wg.x;
        let bounds = tile_bounds(lid, tile_index);
        let opaque = bounds.x <= bounds.y;
        let mut lists = 1u32;
        if PARAMS.transparent != 0u32 {
            lists = 2u32;
        }
        if !opaque && lists == 1u32 {
            // Sky only and nothing blended: no surface in this tile, so no item can touch it.
            if lid == 0u32 {
                lists_clear(tile_index, 1u32);
            }
            return;
        }
        let far = depth_to_view(f32::from_bits(bounds.y));
        let transparent_far = depth_to_view(f32::from_bits(bounds.w));
        let range = TileRange {
            opaque,
            near: depth_to_view(f32::from_bits(bounds.x)),
            far,
            mask: bounds.z,
            transparent_near: depth_to_view(0.0),
            transparent_far,
        };

        // The tile frustum's sides from the projection rows (Gribb/Hartmann).
        let r = tile_ndc(wg.xy(), tile, PARAMS.screen);
        let sides = side_planes(PARAMS.projection, r);
        let rays = tile_rays(PARAMS.inv_projection, PARAMS.orthographic, r);

        let st = super_tile_of(wg.xy(), tile);
        let coarse = reads_coarse(st);
        let n = candidate_count(st, coarse);
        lists_reset(lid);
        workgroup_barrier();
        // Count every list and keep the hits; allocate; write the hits (or, when they did not
        // fit in workgroup memory, classify again and write).
        let mut i = lid;
        while i < n {
            let hit = candidate_lists(st, coarse, i, sides, rays, range);
            hit_add(hit.y, hit.x);
            i += WORKGROUP;
        }
        workgroup_barrier();
        if lid == 0u32 {
            lists_allocate(tile_index, lists);
        }
        workgroup_barrier();
        let cached = hits_write(lid, WORKGROUP);
        if !cached {
            let mut i = lid;
            while i < n {
                let hit = candidate_lists(st, coarse, i, sides, rays, range);
                list_add(hit.y, hit.x, 1u32);
                i += WORKGROUP;
            }
        }
        box_lists_order(lid, lists, WORKGROUP);
    }
}
