//! The first two levels of the culling hierarchy: per-tile depth information from the pre-Z
//! buffer, then per-super-tile candidate lists.

/// `tile_depth` (one workgroup per `tile`×`tile` tile) reduces the tile's surface samples (sky,
/// depth 1, excluded) to `TILE_DEPTH[tile] = (min depth bits, max depth bits, 2.5D mask, occupied
/// slices)`: the 2.5D mask cuts the tile's view-depth range into 32 cells and sets those holding
/// a sample (Harada 2012); the slice set has bit `k` when a sample lies in clustered depth slice
/// `k` (`light_grid::slice_of`). A sky-only tile has min > max.
///
/// It also folds the tile's range into its 128×128-pixel super-tile's (two words of `COARSE`).
///
/// `coarse_cull` (one invocation per item) scatters each item to the super-tiles whose frustum
/// it reaches: the sides are separable (a column's planes and a row's), so an item tests each
/// column and, within the columns it reaches, each row, then the super-tile's depth range, and
/// appends itself, with its view-space sphere, to the super-tile's candidates (one global atomic
/// per item and super-tile; counts cleared by the host). It also writes every item's view-space
/// sphere for the fallback. With blended surfaces (`transparent`) the depth range is the whole
/// view depth range, and with `all_slices` (clustered lists for every slice) it is unbounded, so
/// the candidates are a superset of whatever the fine level lists. A super-tile with more survivors than its
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
            if min_bits <= max_bits {
                // The super-tile's range: the words start at 0 (cleared), so the minimum is
                // kept inverted and both are maxima.
                let st = super_tile_of(wg.xy(), tile);
                COARSE[super_range_slot(st)].fetch_max(0xffff_ffffu32 - min_bits);
                COARSE[super_range_slot(st) + 1u32].fetch_max(max_bits);
            }
        }
    }

    /// A super-tile's depth range `(near, far)` in view depth, or `None`-like `(1, 0)` when it
    /// lists nothing (no surface, nothing blended, not every slice).
    fn super_range(st: u32) -> Vec2 {
        let inverted_min = COARSE[super_range_slot(st)].load();
        let max_bits = COARSE[super_range_slot(st) + 1u32].load();
        let mut range = Vec2::new(1.0, 0.0);
        if PARAMS.all_slices != 0u32 {
            range = Vec2::new(0.0, UNBOUNDED);
        } else if PARAMS.transparent != 0u32 {
            range = Vec2::new(depth_to_view(0.0), depth_to_view(1.0));
        } else if inverted_min != 0u32 {
            let min_bits = 0xffff_ffffu32 - inverted_min;
            range = Vec2::new(
                depth_to_view(f32::from_bits(min_bits)),
                depth_to_view(f32::from_bits(max_bits)),
            );
        }
        range
    }

    /// NDC `x` of super-tile column boundary `i` (pixel `i · SUPER_TILE_PIXELS`).
    fn column_ndc(i: u32) -> f32 {
        2.0 * i as f32 * SUPER_TILE_PIXELS as f32 / PARAMS.screen.x as f32 - 1.0
    }

    /// NDC `y` of super-tile row boundary `j`.
    fn row_ndc(j: u32) -> f32 {
        1.0 - 2.0 * j as f32 * SUPER_TILE_PIXELS as f32 / PARAMS.screen.y as f32
    }

    #[compute(workgroup_size(256, 1, 1))]
    pub fn coarse_cull(#[builtin(global_invocation_id)] gid: UVec3) {
        let item = gid.x;
        if item >= PARAMS.item_count {
            return;
        }
        let s = view_sphere(item);
        SPHERES[view_sphere_slot(item)] = s;
        let c = s.xyz();
        let r = s.w;
        // The super-tile frustum test is separable: a column's two side planes depend only on
        // the column, a row's only on the row (the planes are `light_grid::side_planes`'s, so
        // the result is that of testing each super-tile's frustum in full).
        let m = PARAMS.projection;
        let row0 = Vec4::new(m.x_axis.x, m.y_axis.x, m.z_axis.x, m.w_axis.x);
        let row1 = Vec4::new(m.x_axis.y, m.y_axis.y, m.z_axis.y, m.w_axis.y);
        let row3 = Vec4::new(m.x_axis.w, m.y_axis.w, m.z_axis.w, m.w_axis.w);
        for i in 0u32..PARAMS.super_tiles.x {
            let left = normalized_plane(row0 - column_ndc(i) * row3);
            let right = normalized_plane(column_ndc(i + 1u32) * row3 - row0);
            let column = left.xyz().dot(c) + left.w >= -r && right.xyz().dot(c) + right.w >= -r;
            if column {
                for j in 0u32..PARAMS.super_tiles.y {
                    let bottom = normalized_plane(row1 - row_ndc(j + 1u32) * row3);
                    let top = normalized_plane(row_ndc(j) * row3 - row1);
                    let row =
                        bottom.xyz().dot(c) + bottom.w >= -r && top.xyz().dot(c) + top.w >= -r;
                    let st = j * PARAMS.super_tiles.x + i;
                    let range = super_range(st);
                    let depth = -c.z - range.x >= -r && c.z + range.y >= -r;
                    if row && range.x <= range.y && depth {
                        let slot = COARSE[st].fetch_add(1u32);
                        if slot < PARAMS.coarse_stride {
                            COARSE[coarse_slot(st, slot)].store(item);
                            SPHERES[st * PARAMS.coarse_stride + slot] = s;
                        } else if slot == PARAMS.coarse_stride {
                            COUNTERS[COARSE_FALLBACKS].fetch_add(1u32);
                        }
                    }
                }
            }
        }
    }
}
