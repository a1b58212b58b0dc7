//! What the three culling dispatches share: their parameters, the item and list bindings, the
//! coarse candidate lists between the levels of the hierarchy, and the count-then-write append
//! that makes every list complete whatever its length.

/// The bindings and steps of the culling hierarchy (`cull_prepare` → `tile_cull` or
/// `cluster_cull`):
///
/// * `TILE_DEPTH` (binding 6): per screen tile, the depth bounds of its surface samples, the
///   2.5D geometry mask and the occupied depth slices (written by `cull_prepare::tile_depth`);
/// * `COARSE` (binding 7): per 128×128-pixel super-tile its candidate count, its depth ranges
///   (three words, from `cull_prepare::tile_depth`) and `coarse_stride` slots of the items that can
///   touch it (written by `cull_prepare::coarse_cull`); the host clears counts and ranges each
///   frame. A super-tile whose count exceeds its slots has its tiles test every item, so
///   nothing is ever lost;
/// * `SPHERES` (binding 8): the candidates' view-space spheres, slot for slot, so a tile loads an
///   item index only for the candidates it keeps; after them every item's view-space sphere,
///   written once by the same pass, for the fallback. (Seven storage buffers in all: WebGPU's
///   default limit is eight per stage.)
/// * the output: `GRID` (binding 2) holds `(offset, count)` per list, `INDICES` (binding 3) the
///   items, `COUNTERS` (binding 4) the overflow counters.
///
/// A fine cell (a tile) owns up to [`MAX_LISTS`] lists: list `j` of tile `t` is grid entry
/// `t + j · tile_count`. Tiled culling has the opaque list (`j = 0`) and, for blended surfaces,
/// the transparent one (`j = 1`); clustered culling has one list per depth slice. A fine kernel
/// classifies each candidate into a bit set of lists and counts it (`hit_add`), allocates every
/// list of the tile with one global atomic (`lists_allocate`), then writes its hits from
/// workgroup memory (`hits_write`), or, when more than [`MAX_HITS`] did not fit there,
/// classifies its candidates again and writes (`list_add` phase 1). Lists have no per-cell limit; only the index list's capacity can run out,
/// and then the tile's lists are dropped whole and counted, for the host to grow the list.
#[shader_dsl::library]
pub mod cull_append {
    /// An item's bounding sphere in world space.
    pub struct CullSphere {
        pub center: Vec3,
        pub radius: f32,
    }

    /// Camera, grid and capacities of the three culling dispatches.
    pub struct CullParams {
        pub view: Mat4,
        pub projection: Mat4,
        pub inv_projection: Mat4,
        /// Target size in pixels.
        pub screen: UVec2,
        /// Tiles across and down.
        pub tiles: UVec2,
        /// Super-tiles across and down.
        pub super_tiles: UVec2,
        /// Items in `ITEMS`.
        pub item_count: u32,
        /// Entries `INDICES` may hold; the buffer may be larger (guard regions).
        pub index_capacity: u32,
        /// Candidate slots per super-tile in `COARSE`.
        pub coarse_stride: u32,
        /// Non-zero: skip the super-tile level, every tile tests every item (brute force).
        pub brute_force: u32,
        /// Non-zero when blended surfaces, which pre-Z does not hold, are shaded: tiled culling
        /// writes a second list per tile spanning from the near plane to the tile's farthest
        /// opaque sample (the far plane for sky-only tiles).
        pub transparent: u32,
        /// Non-zero: clustered culling lists every depth slice, not only those holding a sample.
        pub all_slices: u32,
        /// Depth slices of the clustered grid (at most `MAX_LISTS`).
        pub slices: u32,
        /// View depth where slice 1 starts.
        pub slice_near: f32,
        /// View depth where the last slice starts.
        pub slice_far: f32,
        /// Non-zero: narrow each list with the view-space box of its tile's or froxel's frustum.
        /// Only exact when every shaded point is a sample position (no MSAA): an MSAA edge
        /// fragment is shaded at its pixel centre, extrapolated past its triangle and possibly
        /// outside the tile's depth range, where only the looser plane test happens to list
        /// the lights that reach it (measured: the grazing test at MSAA 4).
        pub box_test: u32,
    }

    /// Most lists one tile owns (and most depth slices of the clustered grid).
    pub const MAX_LISTS: u32 = 32;
    /// Items a tile keeps with their list bits between counting and writing (workgroup
    /// memory); a tile with more re-tests its candidates instead.
    pub const MAX_HITS: u32 = 512;
    /// Edge of a super-tile in pixels.
    pub const SUPER_TILE_PIXELS: u32 = 128;
    /// Invocations per workgroup of the super-tile pass (one per item).
    pub const COARSE_CHUNK: u32 = 256;
    /// `COUNTERS[NEXT_INDEX]`: entries allocated in `INDICES` (may exceed the capacity).
    pub const NEXT_INDEX: u32 = 0;
    /// `COUNTERS[COARSE_FALLBACKS]`: super-tiles whose candidates did not fit their slots.
    pub const COARSE_FALLBACKS: u32 = 1;
    /// `COUNTERS[DROPPED]`: list entries dropped because the index list was full.
    pub const DROPPED: u32 = 2;
    /// `COUNTERS[MAX_CELL_ITEMS]`: the longest list written.
    pub const MAX_CELL_ITEMS: u32 = 3;
    /// Number of counters.
    pub const COUNTER_COUNT: u32 = 4;

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
    #[storage(group = 0, binding = 6, read_write)]
    static TILE_DEPTH: [UVec4];
    /// Per super-tile its candidate count (the first `super_tiles.x · super_tiles.y` words,
    /// cleared by the host), then its `coarse_stride` candidate slots.
    #[storage(group = 0, binding = 7, read_write)]
    static COARSE: [Atomic<u32>];
    /// The candidates' view-space spheres, slot for slot, then every item's view-space sphere.
    #[storage(group = 0, binding = 8, read_write)]
    static SPHERES: [Vec4];

    #[workgroup]
    static LIST_COUNT: [Atomic<u32>; MAX_LISTS];
    #[workgroup]
    static LIST_BASE: [u32; MAX_LISTS];
    #[workgroup]
    static LIST_ROOM: u32;
    #[workgroup]
    static HIT_COUNT: Atomic<u32>;
    #[workgroup]
    static HITS: [UVec2; MAX_HITS];

    /// An item's bounding sphere in view space: centre in `xyz`, radius in `w`.
    fn view_sphere(item: u32) -> Vec4 {
        let sphere = ITEMS[item];
        let c = (PARAMS.view * sphere.center.extend(1.0)).xyz();
        c.extend(sphere.radius)
    }

    /// The super-tile holding tile `t` of `tile_size` pixels.
    fn super_tile_of(t: UVec2, tile_size: u32) -> u32 {
        let s = t / (SUPER_TILE_PIXELS / tile_size);
        s.y * PARAMS.super_tiles.x + s.x
    }

    /// Whether the tiles of `super_tile` read its coarse list (not brute force, and the list
    /// fitted); otherwise they test every item.
    fn reads_coarse(super_tile: u32) -> bool {
        PARAMS.brute_force == 0u32 && COARSE[super_tile].load() <= PARAMS.coarse_stride
    }

    /// How many candidates the tiles of `super_tile` test.
    fn candidate_count(super_tile: u32, coarse: bool) -> u32 {
        let mut n = PARAMS.item_count;
        if coarse {
            n = COARSE[super_tile].load();
        }
        n
    }

    /// Super-tiles of the frame.
    fn super_tile_count() -> u32 {
        PARAMS.super_tiles.x * PARAMS.super_tiles.y
    }

    /// Where the three depth words of `super_tile` live in `COARSE` (after the counts): the
    /// inverted min and the max of its opaque depth bits, and the max its blended surfaces reach.
    fn super_range_slot(super_tile: u32) -> u32 {
        super_tile_count() + 3u32 * super_tile
    }

    /// Where candidate slot `i` of `super_tile` lives in `COARSE` (after counts and ranges).
    fn coarse_slot(super_tile: u32, i: u32) -> u32 {
        4u32 * super_tile_count() + super_tile * PARAMS.coarse_stride + i
    }

    /// Where item `item`'s view-space sphere lives in `SPHERES`.
    fn view_sphere_slot(item: u32) -> u32 {
        super_tile_count() * PARAMS.coarse_stride + item
    }

    /// The item of candidate `i` of `super_tile` (loaded only for candidates that are kept).
    fn candidate_item(super_tile: u32, coarse: bool, i: u32) -> u32 {
        let mut item = i;
        if coarse {
            item = COARSE[coarse_slot(super_tile, i)].load();
        }
        item
    }

    /// The view-space sphere of candidate `i` of `super_tile`: stored next to it in the coarse
    /// list, or, without one, from the items' spheres (which the super-tile pass fills) or
    /// transformed here (brute force, where that pass does not run).
    fn candidate_sphere(super_tile: u32, coarse: bool, i: u32) -> Vec4 {
        let mut s = Vec4::ZERO;
        if coarse {
            s = SPHERES[super_tile * PARAMS.coarse_stride + i];
        } else if PARAMS.brute_force != 0u32 {
            s = view_sphere(i);
        } else {
            s = SPHERES[view_sphere_slot(i)];
        }
        s
    }

    /// Zeroes the per-list counters and the hit cache; invocations `0..MAX_LISTS` call it,
    /// before a barrier.
    fn lists_reset(lid: u32) {
        if lid < MAX_LISTS {
            LIST_COUNT[lid].store(0u32);
        }
        if lid == 0u32 {
            HIT_COUNT.store(0u32);
        }
    }

    /// Counting phase: counts candidate `i` of `super_tile` in the lists of `bits` and keeps
    /// its item, with its bits, in the hit cache while there is room.
    fn hit_add(bits: u32, super_tile: u32, coarse: bool, i: u32) {
        if bits != 0u32 {
            let item = candidate_item(super_tile, coarse, i);
            list_add(bits, item, 0u32);
            let h = HIT_COUNT.fetch_add(1u32);
            if h < MAX_HITS {
                HITS[h] = UVec2::new(item, bits);
            }
        }
    }

    /// Writing phase from the hit cache (after `lists_allocate` and a barrier), spread over
    /// `threads` invocations. Returns `false`, writing nothing, when the hits did not fit: the
    /// caller then classifies its candidates again with `list_add(.., 1)`.
    fn hits_write(lid: u32, threads: u32) -> bool {
        let n = HIT_COUNT.load();
        let fits = n <= MAX_HITS;
        if fits {
            let mut i = lid;
            while i < n {
                let h = HITS[i];
                list_add(h.y, h.x, 1u32);
                i += threads;
            }
        }
        fits
    }

    /// Phase 0 counts `item` in every list of `bits`; phase 1 writes it there (`bits` 0: nothing).
    fn list_add(bits: u32, item: u32, phase: u32) {
        let mut rest = bits;
        while rest != 0u32 {
            let j = rest.trailing_zeros();
            rest = rest & (rest - 1u32);
            let slot = LIST_COUNT[j].fetch_add(1u32);
            if phase == 1u32 && LIST_ROOM != 0u32 {
                INDICES[LIST_BASE[j] + slot] = item;
            }
        }
    }

    /// Between the phases (invocation 0, after a barrier): one global allocation for the `lists`
    /// lists of tile `tile`, their grid entries, and the counters reset for the write phase. A
    /// tile whose lists do not fit the index list gets empty lists; its entries are counted as
    /// dropped.
    fn lists_allocate(tile: u32, lists: u32) {
        let tile_count = PARAMS.tiles.x * PARAMS.tiles.y;
        let mut total = 0u32;
        let mut longest = 0u32;
        for j in 0u32..lists {
            let n = LIST_COUNT[j].load();
            total += n;
            longest = longest.max(n);
        }
        let offset = COUNTERS[NEXT_INDEX].fetch_add(total);
        COUNTERS[MAX_CELL_ITEMS].fetch_max(longest);
        let mut room = 1u32;
        if offset > PARAMS.index_capacity || PARAMS.index_capacity - offset < total {
            room = 0u32;
            COUNTERS[DROPPED].fetch_add(total);
        }
        let mut base = offset;
        for j in 0u32..lists {
            let n = LIST_COUNT[j].load();
            LIST_BASE[j] = base;
            GRID[tile + j * tile_count] = UVec2::new(base, n * room);
            base += n;
            LIST_COUNT[j].store(0u32);
        }
        LIST_ROOM = room;
    }

    /// Empty lists `0..lists` for tile `tile` (invocation 0).
    fn lists_clear(tile: u32, lists: u32) {
        let tile_count = PARAMS.tiles.x * PARAMS.tiles.y;
        for j in 0u32..lists {
            GRID[tile + j * tile_count] = UVec2::new(0u32, 0u32);
        }
    }
}
