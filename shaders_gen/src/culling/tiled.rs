//! Tiled and 2.5D light culling: one workgroup per screen tile.

/// Tiled culling (Harada's Forward+, reference 000): one workgroup per `tile`×`tile` tile, and
/// with `depth_mask` the 2.5D variant (Harada 2012).
///
/// Each workgroup reduces the tile's depth bounds from the pre-Z buffer, builds the tile
/// frustum, tests every item's bounding sphere with the items spread over its threads, gathers
/// survivors in workgroup memory, and appends them to the global index list through one atomic
/// per tile. The grid gets `(offset, count)` per tile (reference 002's layout).
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

    /// An item's bounding sphere in world space.
    pub struct CullSphere {
        pub center: Vec3,
        pub radius: f32,
    }

    /// Largest per-tile list the workgroup can gather (workgroup memory).
    pub const MAX_PER_TILE: u32 = 1024;
    /// `COUNTERS[NEXT_INDEX]`: entries allocated in `INDICES` (may exceed the capacity).
    pub const NEXT_INDEX: u32 = 0;
    /// `COUNTERS[OVERFLOW_TILES]`: tiles that found more items than `max_per_tile`.
    pub const OVERFLOW_TILES: u32 = 1;
    /// `COUNTERS[DROPPED]`: list entries dropped for lack of room (per tile or in total).
    pub const DROPPED: u32 = 2;
    /// `COUNTERS[MAX_TILE_ITEMS]`: the most items any tile found.
    pub const MAX_TILE_ITEMS: u32 = 3;
    /// Number of counters.
    pub const COUNTER_COUNT: u32 = 4;

    const TILE_THREADS: u32 = tile * tile;
    /// Cells of the 2.5D depth mask.
    pub const MASK_CELLS: u32 = 32;
    const INFINITY_BITS: u32 = 0x7f80_0000;

    #[uniform(group = 0, binding = 0)]
    static PARAMS: CullParams;
    #[storage(group = 0, binding = 1)]
    static ITEMS: [CullSphere];
    #[storage(group = 0, binding = 2, read_write)]
    static GRID: [UVec2];
    #[storage(group = 0, binding = 3, read_write)]
    static INDICES: [u32];
    #[storage(group = 0, binding = 4, read_write)]
    static COUNTERS: [Atomic<u32>];
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
    static TILE_COUNT: Atomic<u32>;
    #[workgroup]
    static TILE_LIST: [u32; MAX_PER_TILE];
    #[workgroup]
    static TILE_MASK: Atomic<u32>;
    #[workgroup]
    static TILE_BASE: u32;
    #[workgroup]
    static TILE_STORED: u32;

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
    fn view_depth(d: f32) -> f32 {
        let p = PARAMS.inv_projection * Vec4::new(0.0, 0.0, d, 1.0);
        -p.z / p.w
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
                mask = mask | (1u32 << mask_cell(view_depth(d), near, far));
            }
        }
        mask
    }

    /// A plane `n · p + w = 0` from a combination of projection rows, normalised.
    fn normalized_plane(v: Vec4) -> Vec4 {
        v / v.xyz().length()
    }

    /// Whether a view-space sphere clears every plane of the tile frustum.
    fn sphere_in_tile(
        c: Vec3,
        r: f32,
        left: Vec4,
        right: Vec4,
        bottom: Vec4,
        top: Vec4,
        near: f32,
        far: f32,
    ) -> bool {
        let mut inside = left.xyz().dot(c) + left.w >= -r;
        inside = inside && right.xyz().dot(c) + right.w >= -r;
        inside = inside && bottom.xyz().dot(c) + bottom.w >= -r;
        inside = inside && top.xyz().dot(c) + top.w >= -r;
        inside = inside && -c.z - near >= -r;
        inside = inside && c.z + far >= -r;
        inside
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
            TILE_COUNT.store(0u32);
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
        let mut near = view_depth(f32::from_bits(min_bits));
        let mut far = view_depth(f32::from_bits(max_bits));
        if transparent {
            // A blended surface can be anywhere between the eye and the opaque depth.
            near = view_depth(0.0);
            if min_bits > max_bits {
                far = view_depth(1.0);
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
        let m = PARAMS.projection;
        let row0 = Vec4::new(m.x_axis.x, m.y_axis.x, m.z_axis.x, m.w_axis.x);
        let row1 = Vec4::new(m.x_axis.y, m.y_axis.y, m.z_axis.y, m.w_axis.y);
        let row3 = Vec4::new(m.x_axis.w, m.y_axis.w, m.z_axis.w, m.w_axis.w);
        let size = PARAMS.screen.as_vec2();
        let x0 = 2.0 * (wg.x * tile) as f32 / size.x - 1.0;
        let x1 = 2.0 * ((wg.x + 1u32) * tile) as f32 / size.x - 1.0;
        let y1 = 1.0 - 2.0 * (wg.y * tile) as f32 / size.y;
        let y0 = 1.0 - 2.0 * ((wg.y + 1u32) * tile) as f32 / size.y;
        let left = normalized_plane(row0 - x0 * row3);
        let right = normalized_plane(x1 * row3 - row0);
        let bottom = normalized_plane(row1 - y0 * row3);
        let top = normalized_plane(y1 * row3 - row1);

        // 3. Items spread over the threads; survivors gathered in workgroup memory. The trip
        //    count is the same for every thread, so subgroup operations see uniform control flow.
        let rounds = (PARAMS.item_count + TILE_THREADS - 1u32) / TILE_THREADS;
        for round in 0u32..rounds {
            let item = round * TILE_THREADS + lid;
            let mut visible = false;
            if item < PARAMS.item_count {
                let sphere = ITEMS[item];
                let c = (PARAMS.view
                    * Vec4::new(sphere.center.x, sphere.center.y, sphere.center.z, 1.0))
                .xyz();
                visible = sphere_in_tile(c, sphere.radius, left, right, bottom, top, near, far);
                if depth_mask {
                    let light_mask =
                        sphere_mask(-c.z - sphere.radius, -c.z + sphere.radius, near, far);
                    visible = visible && (light_mask & geometry_mask) != 0u32;
                }
            }
            if scalarize {
                let ballot = subgroup_ballot(visible);
                let total = ballot.x.count_ones()
                    + ballot.y.count_ones()
                    + ballot.z.count_ones()
                    + ballot.w.count_ones();
                // `total` is the same on every lane, so this branch keeps the subgroup uniform;
                // rounds where no lane sees an item (most of them) skip the scan and the atomic.
                if total > 0u32 {
                    let rank = subgroup_exclusive_add(select(visible, 1u32, 0u32));
                    let mut base = 0u32;
                    if lane == 0u32 {
                        base = TILE_COUNT.fetch_add(total);
                    }
                    base = subgroup_broadcast_first(base);
                    let slot = base + rank;
                    if visible && slot < PARAMS.max_per_tile {
                        TILE_LIST[slot] = item;
                    }
                }
            } else {
                if visible {
                    let slot = TILE_COUNT.fetch_add(1u32);
                    if slot < PARAMS.max_per_tile {
                        TILE_LIST[slot] = item;
                    }
                }
            }
        }
        workgroup_barrier();

        // 4. One global allocation per tile; overflow is counted, never written.
        if lid == 0u32 {
            let found = TILE_COUNT.load();
            let kept = found.min(PARAMS.max_per_tile);
            COUNTERS[MAX_TILE_ITEMS].fetch_max(found);
            if found > kept {
                COUNTERS[OVERFLOW_TILES].fetch_add(1u32);
            }
            let offset = COUNTERS[NEXT_INDEX].fetch_add(kept);
            let mut room = 0u32;
            if offset < PARAMS.index_capacity {
                room = PARAMS.index_capacity - offset;
            }
            let stored = kept.min(room);
            if found > stored {
                COUNTERS[DROPPED].fetch_add(found - stored);
            }
            TILE_BASE = offset;
            TILE_STORED = stored;
            GRID[tile_index] = UVec2::new(offset, stored);
        }
        workgroup_barrier();
        let base = TILE_BASE;
        let stored = TILE_STORED;
        let mut j = lid;
        while j < stored {
            INDICES[base + j] = TILE_LIST[j];
            j += TILE_THREADS;
        }
    }
}
