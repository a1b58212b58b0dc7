//! Clustered light culling, the fine level: froxels of one screen tile × an exponential depth
//! slice (Olsson's clustered shading; DOOM 2016 and Call of Duty slice depth exponentially).

/// Clustered culling over the candidates `cull_prepare` left for the tile's super-tile: one
/// workgroup per `tile`×`tile` screen tile, one list per depth slice.
///
/// Slice `k` of `slices` spans view depths `slice_near·(slice_far/slice_near)^(k/slices)` to the
/// next; slice 0 reaches the eye and the last goes to infinity (`light_grid::slice_start`). The
/// list of slice `k` is grid entry `tile + k · tile_count` (`light_grid::froxel_cell`).
///
/// An item is listed in froxel `(tile, k)` when its sphere clears the tile's four side planes and
/// the slice's two depth planes and, with `box_test` (single-sample frames), reaches the
/// froxel's view-space bounding box (closest point of the box within the radius; the last slice,
/// unbounded, has none). Without `all_slices`, only the slices holding a depth sample of the
/// tile (`TILE_DEPTH[tile].w`) get lists, and each froxel is clipped to the tile's sample depth
/// range (every shaded point is then a sample), so a froxel's list is never longer than its
/// tile's would be. A box item (decal) must also reach the froxel as a box: its corners against
/// the planes and, with `box_test`, its axis-aligned box against the froxel's. Lists are counted, allocated with one atomic per tile
/// and written (`cull_append`), so none is cut short.
#[shader_dsl::shader(
    axes(tile: u32 = [8, 16, 32] => "t"),
    uses(crate::shared::light_grid, crate::shared::cull_append),
)]
pub mod cluster_cull {
    /// Invocations per tile.
    pub const WORKGROUP: u32 = 64;
    /// Stands for an unbounded view depth (`light_grid::slice_start` past the last slice).
    const UNBOUNDED: f32 = 3.0e38;

    /// View depth where each slice starts, and `slices` → unbounded (computed once per
    /// workgroup: `powf` per candidate and slice would dominate the kernel).
    #[workgroup]
    static SLICE_START: [f32; MAX_LISTS + 1u32];

    /// The tile's column of froxels: side planes, its corner rays and the slices that get
    /// lists.
    struct TileColumn {
        sides: SidePlanes,
        rays: TileRays,
        slices: u32,
        /// The view depths the froxels are clipped to: the tile's sample range when only
        /// occupied slices are listed (every shaded point is then a sample), else unbounded.
        depth_lo: f32,
        depth_hi: f32,
    }

    /// The slices (bit `k`) whose froxel of this tile the view-space sphere `s` reaches.
    fn classify(s: Vec4, column: TileColumn) -> u32 {
        let c = s.xyz();
        let r = s.w;
        let slices = PARAMS.slices;
        let mut bits = 0u32;
        let hi = -c.z + r;
        if hi >= 0.0 && sphere_in_frustum(c, r, column.sides, 0.0, hi) {
            // The slices the sphere's depth span touches, widened by one for rounding; the exact
            // per-slice test decides.
            let lo = -c.z - r;
            let mut first = 0u32;
            if lo > PARAMS.slice_near {
                first = slice_of(lo, PARAMS.slice_near, PARAMS.slice_far, slices).max(1u32) - 1u32;
            }
            let mut last = slices - 1u32;
            if hi > PARAMS.slice_near {
                last = (slice_of(hi, PARAMS.slice_near, PARAMS.slice_far, slices) + 1u32)
                    .min(slices - 1u32);
            } else {
                last = 1u32.min(slices - 1u32);
            }
            for k in first..last + 1u32 {
                if (column.slices & (1u32 << k)) != 0u32 {
                    let zn = SLICE_START[k].max(column.depth_lo);
                    let zf = SLICE_START[k + 1u32].min(column.depth_hi);
                    let mut hit = -c.z - zn >= -r && c.z + zf >= -r;
                    if hit && zf < UNBOUNDED && PARAMS.box_test != 0u32 {
                        hit = sphere_reaches_box(c, r, column.rays, zn, zf);
                    }
                    if hit {
                        bits = bits | (1u32 << k);
                    }
                }
            }
        }
        bits
    }

    /// Of the slices `bits` (those the box's bounding sphere reaches), the ones whose froxel of
    /// this tile the view-space box `b` reaches: its corners against the planes, and with
    /// `box_test` its axis-aligned box against the froxel's.
    fn classify_box(b: ViewBox, column: TileColumn, bits: u32) -> u32 {
        let c = b.center;
        let e = box_extent(b.x, b.y, b.z);
        let mut kept = 0u32;
        if box_in_frustum(c, b.x, b.y, b.z, column.sides, 0.0, UNBOUNDED) {
            let mut rest = bits;
            while rest != 0u32 {
                let k = rest.trailing_zeros();
                rest = rest & (rest - 1u32);
                let zn = SLICE_START[k].max(column.depth_lo);
                let zf = SLICE_START[k + 1u32].min(column.depth_hi);
                let mut hit = -c.z - zn >= -e.z && c.z + zf >= -e.z;
                if hit && zf < UNBOUNDED && PARAMS.box_test != 0u32 {
                    hit = box_reaches_box(c, e, column.rays, zn, zf);
                }
                if hit {
                    kept = kept | (1u32 << k);
                }
            }
        }
        kept
    }

    /// Candidate `i`'s item (`x`) and its slices (`y`): its bounding sphere decides, and a box
    /// item must pass its box's test as well. The item index is loaded only for a hit.
    fn candidate_lists(st: u32, coarse: bool, i: u32, column: TileColumn) -> UVec2 {
        let mut bits = classify(candidate_sphere(st, coarse, i), column);
        let mut item = 0u32;
        if bits != 0u32 {
            item = candidate_item(st, coarse, i);
            if is_box(item) {
                bits = classify_box(view_box(item), column, bits);
            }
        }
        UVec2::new(item, bits)
    }

    #[compute(workgroup_size(64, 1, 1))]
    pub fn cull(#[builtin(local_invocation_index)] lid: u32, #[builtin(workgroup_id)] wg: UVec3) {
        let tile_index = wg.y * PARAMS.tiles.x + wg.x;
        let lists = PARAMS.slices;
        let bounds = tile_bounds(lid, tile_index);
        let mut slices = bounds.w;
        let mut depth_lo = 0.0;
        let mut depth_hi = UNBOUNDED;
        if PARAMS.all_slices != 0u32 {
            slices = 0xffff_ffffu32 >> (MAX_LISTS - lists);
        } else if slices != 0u32 {
            depth_lo = view_depth(PARAMS.inv_projection, f32::from_bits(bounds.x));
            depth_hi = view_depth(PARAMS.inv_projection, f32::from_bits(bounds.y));
        }
        if slices == 0u32 {
            // No sample in any slice: every froxel of the column stays empty.
            if lid == 0u32 {
                lists_clear(tile_index, lists);
            }
            return;
        }
        let r = tile_ndc(wg.xy(), tile, PARAMS.screen);
        let column = TileColumn {
            sides: side_planes(PARAMS.projection, r),
            rays: tile_rays(PARAMS.inv_projection, PARAMS.orthographic, r),
            slices,
            depth_lo,
            depth_hi,
        };

        let st = super_tile_of(wg.xy(), tile);
        let coarse = reads_coarse(st);
        let n = candidate_count(st, coarse);
        lists_reset(lid);
        if lid <= lists {
            SLICE_START[lid] = slice_start(lid, PARAMS.slice_near, PARAMS.slice_far, lists);
        }
        workgroup_barrier();
        // Count every list and keep the hits; allocate; write the hits (or, when they did not
        // fit in workgroup memory, classify again and write).
        let mut i = lid;
        while i < n {
            let hit = candidate_lists(st, coarse, i, column);
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
                let hit = candidate_lists(st, coarse, i, column);
                list_add(hit.y, hit.x, 1u32);
                i += WORKGROUP;
            }
        }
        box_lists_order(lid, lists, WORKGROUP);
    }
}
