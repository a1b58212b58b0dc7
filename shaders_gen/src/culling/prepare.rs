//! The first two levels of the culling hierarchy: per-tile depth information from the pre-Z
//! buffer, then per-super-tile candidate lists.

/// `tile_depth` (one workgroup per `tile`×`tile` tile) reduces the tile's surface samples (sky,
/// depth 1, excluded) to `TILE_DEPTH[tile] = (min depth bits, max depth bits, 2.5D mask, last)`:
/// the 2.5D mask cuts the tile's view-depth range into 32 cells and sets those holding a sample
/// (Harada 2012); `last` is, for clustered culling, the set of occupied slices (bit `k` when a
/// sample lies in depth slice `k`, `light_grid::slice_of`) and, for tiled culling, the depth
/// bits blended surfaces can reach (the far plane when a sample is sky, else the max). A
/// sky-only tile has min > max.
///
/// It also folds the tile's range into its 128×128-pixel super-tile's (two words of `COARSE`).
///
/// `coarse_cull` (one workgroup per super-tile and chunk of `COARSE_CHUNK` items, so that even a
/// few super-tiles fill the GPU) tests each item against the super-tile's frustum and appends
/// the survivors, with their view-space spheres, to the super-tile's candidates (a global atomic
/// on its count; counts cleared by the host). Super-tile 0's workgroups also write every item's
/// view-space sphere, for the fallback. The depth range is the super-tile's opaque range; with
/// blended surfaces (`transparent`) it runs from the near plane to the farthest depth its
/// blended surfaces can reach, and with `all_slices` (clustered lists for every slice) it is
/// unbounded, so the candidates are a superset of whatever the fine level lists. A super-tile with more survivors than its
/// `coarse_stride` slots (counted once in `COUNTERS[COARSE_FALLBACKS]`) has its tiles test every
/// item: slower, but complete.
#[shader_dsl::shader(
    axes(
        tile: u32 = [8, 16, 32] => "t",
        msaa: u32 = [1, 2, 4, 8],
        vis64: bool = [false, true] => "vis64",
    ),
    uses(
        crate::shared::light_grid,
        crate::shared::cull_append,
        crate::visibility::samples64::vis64_sample,
    ),
)]
pub mod cull_prepare {
    const TILE_THREADS: u32 = tile * tile;
    /// Tiles across one super-tile.
    const TILES_PER_SUPER: u32 = SUPER_TILE_PIXELS / tile;
    /// Stands for an unbounded view depth (as `light_grid`'s own).
    const UNBOUNDED: f32 = 3.0e38;
    const INFINITY_BITS: u32 = 0x7f80_0000;

    #[texture(group = 0, binding = 5)]
    #[when(msaa == 1 && !vis64)]
    static DEPTH: TextureDepth2d;
    #[texture(group = 0, binding = 5)]
    #[when(msaa > 1 && !vis64)]
    static DEPTH_MS: TextureDepthMultisampled2d;
    /// With `vis64`, in place of the depth buffer: the compute rasteriser's samples
    /// (`vis_compute_raster`'s `VIS64`) as `(low, high)` word pairs, `(y × width + x) × msaa +
    /// s`; a sample's depth is `bitcast(!high)`, or sky where both words are 0.
    #[storage(group = 0, binding = 5)]
    #[when(vis64)]
    static VIS64: [UVec2];

    #[workgroup]
    static RANGE_MIN: Atomic<u32>;
    #[workgroup]
    static RANGE_MAX: Atomic<u32>;
    #[workgroup]
    static TILE_MASK: Atomic<u32>;
    #[workgroup]
    static TILE_SLICES: Atomic<u32>;
    #[workgroup]
    static TILE_SKY: Atomic<u32>;
    #[workgroup]
    static SUPER_SIDES: SidePlanes;
    #[workgroup]
    static SUPER_RANGE: Vec2;

    /// Depth-buffer value of sample `s` of pixel `p`.
    fn sample_depth(p: UVec2, s: u32) -> f32 {
        let mut d = 1.0;
        if vis64 {
            d = vis64_depth(VIS64[(p.y * PARAMS.screen.x + p.x) * msaa + s]);
        } else if msaa == 1 {
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
            TILE_SKY.store(0u32);
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
                } else {
                    TILE_SKY.store(1u32);
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
            // Blended surfaces reach the far plane above a sky sample, else the farthest opaque
            // one (they are depth-tested against pre-Z).
            let mut blend_far_bits = max_bits;
            if TILE_SKY.load() != 0u32 || min_bits > max_bits {
                blend_far_bits = 1.0f32.to_bits();
            }
            let mut last = TILE_SLICES.load();
            if PARAMS.slices == 0u32 {
                last = blend_far_bits;
            }
            TILE_DEPTH[t] = UVec4::new(min_bits, max_bits, TILE_MASK.load(), last);
            // The super-tile's ranges: the words start at 0 (cleared), so the minimum is kept
            // inverted and all three are maxima.
            let st = super_tile_of(wg.xy(), tile);
            if min_bits <= max_bits {
                COARSE[super_range_slot(st)].fetch_max(0xffff_ffffu32 - min_bits);
                COARSE[super_range_slot(st) + 1u32].fetch_max(max_bits);
            }
            COARSE[super_range_slot(st) + 2u32].fetch_max(blend_far_bits);
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
            let blend_far_bits = COARSE[super_range_slot(st) + 2u32].load();
            range = Vec2::new(
                depth_to_view(0.0),
                depth_to_view(f32::from_bits(blend_far_bits)),
            );
        } else if inverted_min != 0u32 {
            let min_bits = 0xffff_ffffu32 - inverted_min;
            range = Vec2::new(
                depth_to_view(f32::from_bits(min_bits)),
                depth_to_view(f32::from_bits(max_bits)),
            );
        }
        range
    }

    #[compute(workgroup_size(256, 1, 1))]
    pub fn coarse_cull(
        #[builtin(local_invocation_index)] lid: u32,
        #[builtin(workgroup_id)] wg: UVec3,
    ) {
        let st = wg.y * PARAMS.super_tiles.x + wg.x;
        if lid == 0u32 {
            // The super-tile frustum (pixel edges, not clamped to the screen, like tiles),
            // once per workgroup.
            let r = tile_ndc(wg.xy(), SUPER_TILE_PIXELS, PARAMS.screen);
            SUPER_SIDES = side_planes(PARAMS.projection, r);
            SUPER_RANGE = super_range(st);
        }
        workgroup_barrier();
        let item = wg.z * COARSE_CHUNK + lid;
        if item < PARAMS.item_count {
            let s = view_sphere(item);
            if st == 0u32 {
                SPHERES[view_sphere_slot(item)] = s;
            }
            let range = SUPER_RANGE;
            if range.x <= range.y && sphere_in_frustum(s.xyz(), s.w, SUPER_SIDES, range.x, range.y)
            {
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
