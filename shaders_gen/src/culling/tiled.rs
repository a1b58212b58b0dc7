//! Tiled and 2.5D light culling: one workgroup per screen tile.

/// Tiled culling (Harada's Forward+, reference 000): one workgroup per `tile`×`tile` tile, and
/// with `depth_mask` the 2.5D variant (Harada 2012).
///
/// Each workgroup reduces the tile's depth bounds from the pre-Z buffer, builds the tile
/// frustum, tests every item's bounding sphere with the items spread over its threads, gathers
/// survivors in workgroup memory, and appends them to the global index list through one atomic
/// per tile. The grid gets `(offset, count)` per tile (reference 002's layout). The gather, the
/// append, the output bindings and the counters are the `cull_append` library's (shared with
/// `cluster_cull`); planes and the sphere test are `light_grid`'s.
///
/// Capacities are runtime parameters (`max_per_tile` up to [`MAX_PER_TILE`],
/// `index_capacity`); anything that does not fit is counted in `COUNTERS`, never written out of
/// bounds, so the host can report it and grow the buffers. With `scalarize`, the depth
/// reduction uses subgroup min/max before the workgroup atomics, and survivors are appended with
/// a ballot and an exclusive add, one atomic per subgroup.
///
/// 2.5D (`depth_mask`): the tile's depth range is cut into 32 cells; the samples set the bits of
/// the cells holding geometry, each item the bits its sphere spans, and an item is kept only if
/// the two masks share a bit. This drops items that float in the empty space between a near and
/// a far surface of the same tile.
#[shader_dsl::shader(
    axes(
        tile: u32 = [8, 16, 32] => "t",
        msaa: u32 = [1, 2, 4, 8],
        scalarize: bool = [false, true] => "scalar",
        depth_mask: bool = [false, true] => "mask",
    ),
    requires(subgroup = scalarize),
    uses(crate::shared::light_grid, crate::shared::cull_append),
)]
pub mod tile_cull {
    /// Camera and frame parameters of the culling pass.
    pub struct CullParams {
        pub view: Mat4,
        pub projection: Mat4,
        pub inv_projection: Mat4,
        /// Target size in pixels.
        pub screen: UVec2,
        /// Tiles across and down.
        pub tiles: UVec2,
        /// Items in `ITEMS`.
        pub item_count: u32,
        /// Most items one tile may list (at most `MAX_PER_TILE`).
        pub max_per_tile: u32,
        /// Entries `INDICES` may hold; the buffer may be larger (guard regions).
        pub index_capacity: u32,
        /// Non-zero when blended (transparent) surfaces, which pre-Z does not hold, are shaded
        /// with these lists: the tile then spans from the near plane to its farthest opaque
        /// sample (the far plane for sky-only tiles), and the 2.5D mask keeps every cell.
        pub include_transparent: u32,
    }

    /// Largest per-tile list the workgroup can gather (workgroup memory).
    pub const MAX_PER_TILE: u32 = MAX_PER_CELL;
    /// `COUNTERS[OVERFLOW_TILES]`: tiles that found more items than `max_per_tile`.
    pub const OVERFLOW_TILES: u32 = OVERFLOW_CELLS;
    /// `COUNTERS[MAX_TILE_ITEMS]`: the most items any tile found.
    pub const MAX_TILE_ITEMS: u32 = MAX_CELL_ITEMS;

    const TILE_THREADS: u32 = tile * tile;
    /// Cells of the 2.5D depth mask.
    pub const MASK_CELLS: u32 = 32;
    const INFINITY_BITS: u32 = 0x7f80_0000;

    #[uniform(group = 0, binding = 0)]
    static PARAMS: CullParams;
    #[texture(group = 0, binding = 5)]
    #[when(msaa == 1)]
    static DEPTH: TextureDepth2d;
    #[texture(group = 0, binding = 5)]
    #[when(msaa > 1)]
    static DEPTH_MS: TextureDepthMultisampled2d;

    #[workgroup]
    static TILE_MIN: Atomic<u32>;
    #[workgroup]
    static TILE_MAX: Atomic<u32>;
    #[workgroup]
    static TILE_MASK: Atomic<u32>;

    /// Min and max depth over the pixel's surface samples (sky samples, depth 1, excluded).
    fn pixel_depth_bounds(p: UVec2, dmin: &mut f32, dmax: &mut f32) {
        for s in 0u32..msaa {
            let mut d = 1.0;
            if msaa == 1 {
                d = DEPTH.load(p, 0u32);
            } else {
                d = DEPTH_MS.load(p, s);
            }
            if d < 1.0 {
                *dmin = dmin.min(d);
                *dmax = dmax.max(d);
            }
        }
    }

    /// View depth (distance along −Z) of a depth-buffer value.
    fn depth_to_view(d: f32) -> f32 {
        view_depth(PARAMS.inv_projection, d)
    }

    /// The 2.5D mask cell of view depth `d` in the tile's range `[near, far]`.
    fn mask_cell(d: f32, near: f32, far: f32) -> u32 {
        let span = far - near;
        let mut cell = 0u32;
        if span > 0.0 {
            let t = ((d - near) / span * 32.0).floor().max(0.0);
            cell = (t as u32).min(MASK_CELLS - 1u32);
        }
        cell
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

    /// The geometry mask bits of one pixel's surface samples.
    fn pixel_mask(p: UVec2, near: f32, far: f32) -> u32 {
        let mut mask = 0u32;
        for s in 0u32..msaa {
            let mut d = 1.0;
            if msaa == 1 {
                d = DEPTH.load(p, 0u32);
            } else {
                d = DEPTH_MS.load(p, s);
            }
            if d < 1.0 {
                mask = mask | (1u32 << mask_cell(depth_to_view(d), near, far));
            }
        }
        mask
    }

    // One dimension: naga allows subgroup invocation ids only in 1D workgroups.
    #[compute(workgroup_size(tile * tile, 1, 1))]
    pub fn cull(
        #[builtin(local_invocation_index)] lid: u32,
        #[builtin(workgroup_id)] wg: UVec3,
        #[builtin(subgroup_invocation_id)] lane: u32,
    ) {
        if lid == 0u32 {
            TILE_MIN.store(INFINITY_BITS);
            TILE_MAX.store(0u32);
            gather_reset();
            TILE_MASK.store(0u32);
        }
        workgroup_barrier();

        // 1. Depth bounds of the tile's surface samples.
        let pixel = wg.xy() * tile + UVec2::new(lid % tile, lid / tile);
        let mut dmin = 2.0;
        let mut dmax = -1.0;
        if pixel.x < PARAMS.screen.x && pixel.y < PARAMS.screen.y {
            pixel_depth_bounds(pixel, &mut dmin, &mut dmax);
        }
        if scalarize {
            let smin = subgroup_min(dmin);
            let smax = subgroup_max(dmax);
            if lane == 0u32 && smin <= smax {
                TILE_MIN.fetch_min(smin.to_bits());
                TILE_MAX.fetch_max(smax.to_bits());
            }
        } else {
            if dmin <= dmax {
                TILE_MIN.fetch_min(dmin.to_bits());
                TILE_MAX.fetch_max(dmax.to_bits());
            }
        }
        workgroup_barrier();
        let tile_index = wg.y * PARAMS.tiles.x + wg.x;
        let min_bits = TILE_MIN.load();
        let max_bits = TILE_MAX.load();
        let transparent = PARAMS.include_transparent != 0u32;
        if min_bits > max_bits && !transparent {
            // Sky only: no surface in this tile, so no item can touch it.
            if lid == 0u32 {
                GRID[tile_index] = UVec2::new(0u32, 0u32);
            }
            return;
        }
        let mut near = depth_to_view(f32::from_bits(min_bits));
        let mut far = depth_to_view(f32::from_bits(max_bits));
        if transparent {
            // A blended surface can be anywhere between the eye and the opaque depth.
            near = depth_to_view(0.0);
            if min_bits > max_bits {
                far = depth_to_view(1.0);
            }
        }
        let in_screen = pixel.x < PARAMS.screen.x && pixel.y < PARAMS.screen.y;
        if depth_mask {
            // 1b. The geometry's depth mask (2.5D).
            let mut mask = 0u32;
            if in_screen {
                mask = pixel_mask(pixel, near, far);
            }
            if scalarize {
                let m = subgroup_or(mask);
                if lane == 0u32 {
                    TILE_MASK.fetch_or(m);
                }
            } else {
                TILE_MASK.fetch_or(mask);
            }
            workgroup_barrier();
        }
        let mut geometry_mask = TILE_MASK.load();
        if transparent {
            geometry_mask = 0xffff_ffffu32;
        }

        // 2. Tile frustum from the projection rows (Gribb/Hartmann).
        let size = PARAMS.screen.as_vec2();
        let x0 = 2.0 * (wg.x * tile) as f32 / size.x - 1.0;
        let x1 = 2.0 * ((wg.x + 1u32) * tile) as f32 / size.x - 1.0;
        let y1 = 1.0 - 2.0 * (wg.y * tile) as f32 / size.y;
        let y0 = 1.0 - 2.0 * ((wg.y + 1u32) * tile) as f32 / size.y;
        let sides = side_planes(PARAMS.projection, x0, x1, y0, y1);

        // 3. Items spread over the threads; survivors gathered in workgroup memory. The trip
        //    count is the same for every thread, so subgroup operations see uniform control flow.
        let rounds = (PARAMS.item_count + TILE_THREADS - 1u32) / TILE_THREADS;
        // The subgroup lane exists only in scalarized variants.
        let mut lane_id = 0u32;
        if scalarize {
            lane_id = lane;
        }
        for round in 0u32..rounds {
            let item = round * TILE_THREADS + lid;
            let mut visible = false;
            if item < PARAMS.item_count {
                let sphere = ITEMS[item];
                let c = (PARAMS.view
                    * Vec4::new(sphere.center.x, sphere.center.y, sphere.center.z, 1.0))
                .xyz();
                visible = sphere_in_frustum(c, sphere.radius, sides, near, far);
                if depth_mask {
                    let light_mask =
                        sphere_mask(-c.z - sphere.radius, -c.z + sphere.radius, near, far);
                    visible = visible && (light_mask & geometry_mask) != 0u32;
                }
            }
            gather(visible, item, lane_id, PARAMS.max_per_tile);
        }

        // 4. One global allocation per tile; overflow is counted, never written.
        store_list(
            tile_index,
            lid,
            TILE_THREADS,
            PARAMS.max_per_tile,
            PARAMS.index_capacity,
        );
    }
}
