//! The first two levels of the culling hierarchy: per-tile depth information from the pre-Z
//! buffer, then per-super-tile candidate lists.

/// `tile_depth` (one workgroup per `tile`×`tile` tile) reduces the tile's surface samples (sky,
/// depth 1, excluded) to `TILE_DEPTH[tile] = (min depth bits, max depth bits, 2.5D mask, occupied
/// slices)`: the 2.5D mask cuts the tile's view-depth range into 32 cells and sets those holding
/// a sample (Harada 2012); the slice set has bit `k` when a sample lies in clustered depth slice
/// `k` (`light_grid::slice_of`). A sky-only tile has min > max.
///
/// `coarse_cull` (one workgroup per 128×128-pixel super-tile and chunk of `COARSE_CHUNK` items,
/// so that even a few super-tiles fill the GPU) takes the depth range of the super-tile's tiles,
/// builds its frustum and tests the chunk's items against it; the survivors, gathered in
/// workgroup memory and appended, with their view-space spheres, through one global atomic on
/// the super-tile's count in `COARSE` per workgroup (counts cleared by the host), are its tiles'
/// candidates. The workgroups of super-tile 0 also write every item's view-space sphere. With
/// blended surfaces (`transparent`) the range is the whole view depth range, and with
/// `all_slices` (clustered lists for every slice) it is unbounded, so the candidates are a
/// superset of whatever the fine level lists. A super-tile with more survivors than its
/// `coarse_stride` slots (counted once in `COUNTERS[COARSE_FALLBACKS]`) has its tiles test every
/// item: slower, but complete.
#[shader_dsl::shader(
    axes(
        tile: u32 = [8, 16, 32] => "t",
        msaa: u32 = [1, 2, 4, 8],
    ),
    uses(crate::shared::light_grid, crate::shared::cull_append),
)]
pub mod cull_prepare {
    /// Cells of the 2.5D depth mask.
    pub const MASK_CELLS: u32 = 32;
    const TILE_THREADS: u32 = tile * tile;
    /// Tiles across one super-tile.
    const TILES_PER_SUPER: u32 = SUPER_TILE_PIXELS / tile;
    const COARSE_THREADS: u32 = 256;
    /// Stands for an unbounded view depth (as `light_grid`'s own).
    const UNBOUNDED: f32 = 3.0e38;
    const INFINITY_BITS: u32 = 0x7f80_0000;

    #[texture(group = 0, binding = 5)]
    #[when(msaa == 1)]
    static DEPTH: TextureDepth2d;
    #[texture(group = 0, binding = 5)]
    #[when(msaa > 1)]
    static DEPTH_MS: TextureDepthMultisampled2d;

    #[workgroup]
    static RANGE_MIN: Atomic<u32>;
    #[workgroup]
    static RANGE_MAX: Atomic<u32>;
    #[workgroup]
    static TILE_MASK: Atomic<u32>;
    #[workgroup]
    static TILE_SLICES: Atomic<u32>;
    #[workgroup]
    static LOCAL_COUNT: Atomic<u32>;
    #[workgroup]
    static LOCAL_BASE: u32;
    #[workgroup]
    static LOCAL_ITEMS: [u32; COARSE_CHUNK];
    #[workgroup]
    static LOCAL_SPHERES: [Vec4; COARSE_CHUNK];

    /// Depth-buffer value of sample `s` of pixel `p`.
    fn sample_depth(p: UVec2, s: u32) -> f32 {
        let mut d = 1.0;
        if msaa == 1 {
            d = DEPTH.load(p, 0u32);
        } else {
            d = DEPTH_MS.load(p, s);
        }
        d
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

    #[compute(workgroup_size(tile * tile, 1, 1))]
    pub fn tile_depth(
        #[builtin(local_invocation_index)] lid: u32,
        #[builtin(workgroup_id)] wg: UVec3,
    ) {
        if lid == 0u32 {
            RANGE_MIN.store(INFINITY_BITS);
            RANGE_MAX.store(0u32);
            TILE_MASK.store(0u32);
            TILE_SLICES.store(0u32);
        }
        workgroup_barrier();
        let pixel = wg.xy() * tile + UVec2::new(lid % tile, lid / tile);
        let in_screen = pixel.x < PARAMS.screen.x && pixel.y < PARAMS.screen.y;
        let mut dmin = 2.0;
        let mut dmax = -1.0;
        if in_screen {
            for s in 0u32..msaa {
                let d = sample_depth(pixel, s);
                if d < 1.0 {
                    dmin = dmin.min(d);
                    dmax = dmax.max(d);
                }
            }
        }
        if dmin <= dmax {
            RANGE_MIN.fetch_min(dmin.to_bits());
            RANGE_MAX.fetch_max(dmax.to_bits());
        }
        workgroup_barrier();
        let min_bits = RANGE_MIN.load();
        let max_bits = RANGE_MAX.load();
        let near = depth_to_view(f32::from_bits(min_bits));
        let far = depth_to_view(f32::from_bits(max_bits));
        let mut mask = 0u32;
        let mut slices = 0u32;
        if in_screen && min_bits <= max_bits {
            for s in 0u32..msaa {
                let d = sample_depth(pixel, s);
                if d < 1.0 {
                    let v = depth_to_view(d);
                    mask = mask | (1u32 << mask_cell(v, near, far));
                    if PARAMS.slices > 0u32 {
                        let k = slice_of(v, PARAMS.slice_near, PARAMS.slice_far, PARAMS.slices);
                        slices = slices | (1u32 << k);
                    }
                }
            }
        }
        TILE_MASK.fetch_or(mask);
        TILE_SLICES.fetch_or(slices);
        workgroup_barrier();
        if lid == 0u32 {
            let t = wg.y * PARAMS.tiles.x + wg.x;
            TILE_DEPTH[t] = UVec4::new(min_bits, max_bits, TILE_MASK.load(), TILE_SLICES.load());
        }
    }

    #[compute(workgroup_size(256, 1, 1))]
    pub fn coarse_cull(
        #[builtin(local_invocation_index)] lid: u32,
        #[builtin(workgroup_id)] wg: UVec3,
    ) {
        if lid == 0u32 {
            RANGE_MIN.store(INFINITY_BITS);
            RANGE_MAX.store(0u32);
            LOCAL_COUNT.store(0u32);
        }
        workgroup_barrier();
        // 1. The depth range of the super-tile's tiles.
        if lid < TILES_PER_SUPER * TILES_PER_SUPER {
            let t = wg.xy() * TILES_PER_SUPER
                + UVec2::new(lid % TILES_PER_SUPER, lid / TILES_PER_SUPER);
            if t.x < PARAMS.tiles.x && t.y < PARAMS.tiles.y {
                let bounds = TILE_DEPTH[t.y * PARAMS.tiles.x + t.x];
                if bounds.x <= bounds.y {
                    RANGE_MIN.fetch_min(bounds.x);
                    RANGE_MAX.fetch_max(bounds.y);
                }
            }
        }
        workgroup_barrier();
        let min_bits = RANGE_MIN.load();
        let max_bits = RANGE_MAX.load();
        let mut active = min_bits <= max_bits;
        let mut near = depth_to_view(f32::from_bits(min_bits));
        let mut far = depth_to_view(f32::from_bits(max_bits));
        if PARAMS.all_slices != 0u32 {
            active = true;
            near = 0.0;
            far = UNBOUNDED;
        } else if PARAMS.transparent != 0u32 {
            active = true;
            near = depth_to_view(0.0);
            far = depth_to_view(1.0);
        }

        // 2. The super-tile frustum (pixel edges, not clamped to the screen, like tiles).
        let size = PARAMS.screen.as_vec2();
        let edge = SUPER_TILE_PIXELS as f32;
        let x0 = 2.0 * wg.x as f32 * edge / size.x - 1.0;
        let x1 = 2.0 * (wg.x + 1u32) as f32 * edge / size.x - 1.0;
        let y1 = 1.0 - 2.0 * wg.y as f32 * edge / size.y;
        let y0 = 1.0 - 2.0 * (wg.y + 1u32) as f32 * edge / size.y;
        let sides = side_planes(PARAMS.projection, x0, x1, y0, y1);

        // 3. This workgroup's chunk of items against it, survivors gathered in workgroup
        //    memory.
        let st = wg.y * PARAMS.super_tiles.x + wg.x;
        for j in 0u32..COARSE_CHUNK / COARSE_THREADS {
            let item = wg.z * COARSE_CHUNK + j * COARSE_THREADS + lid;
            if item < PARAMS.item_count {
                let s = view_sphere(item);
                if wg.x == 0u32 && wg.y == 0u32 {
                    SPHERES[view_sphere_slot(item)] = s;
                }
                if active && sphere_in_frustum(s.xyz(), s.w, sides, near, far) {
                    let slot = LOCAL_COUNT.fetch_add(1u32);
                    LOCAL_ITEMS[slot] = item;
                    LOCAL_SPHERES[slot] = s;
                }
            }
        }
        workgroup_barrier();
        // 4. One global allocation per workgroup in the super-tile's slots, then the copy.
        let found = LOCAL_COUNT.load();
        if lid == 0u32 {
            let base = COARSE[st].fetch_add(found);
            LOCAL_BASE = base;
            if base <= PARAMS.coarse_stride && base + found > PARAMS.coarse_stride {
                // The first workgroup past the slots counts the super-tile's fallback, once.
                COUNTERS[COARSE_FALLBACKS].fetch_add(1u32);
            }
        }
        workgroup_barrier();
        let base = LOCAL_BASE;
        let mut k = lid;
        while k < found && base + k < PARAMS.coarse_stride {
            COARSE[coarse_slot(st, base + k)].store(LOCAL_ITEMS[k]);
            SPHERES[st * PARAMS.coarse_stride + base + k] = LOCAL_SPHERES[k];
            k += COARSE_THREADS;
        }
    }
}
