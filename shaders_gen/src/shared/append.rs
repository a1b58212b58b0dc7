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
/// * `BOXES` (binding 9): the oriented boxes of the box items (decals). Items `first_box..` are
///   boxes: their `ITEMS` sphere bounds the box (the super-tile level tests that), and the fine
///   level tests the box itself (`light_grid::box_in_frustum`, `box_reaches_box`). The eighth
///   storage buffer of the fine kernels.
/// * the output: `GRID` (binding 2) holds `(offset, count)` per list, `INDICES` (binding 3) the
///   items, `COUNTERS` (binding 4) the overflow counters.
///
/// Item types: every list exists once per type, lights (spheres) first, then decals (boxes);
/// the decal list of grid entry `e` is entry `e + grid_section`. A cell's two ranges are
/// adjacent in `INDICES` (its lights, then its decals), and decal entries hold the decal's
/// index (`item − first_box`), in ascending order: the host orders decals by layer, so a
/// cell's decals come in the order they are applied. Adding a third item type (environment
/// probes) is a third section, not a new list.
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

    /// An oriented box in world space: its centre (`w` unused) and its three axes, each scaled by
    /// the box's half extent along it.
    pub struct CullBox {
        pub center: Vec4,
        pub axis_x: Vec4,
        pub axis_y: Vec4,
        pub axis_z: Vec4,
    }

    /// A box item's box in view space: centre and half-extent axes.
    pub struct ViewBox {
        pub center: Vec3,
        pub x: Vec3,
        pub y: Vec3,
        pub z: Vec3,
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
        /// The first box item (decal): items `first_box..item_count` are `BOXES[item −
        /// first_box]`; `item_count` when there are none.
        pub first_box: u32,
        /// `GRID` entries per item type: a cell's decal list is its light list's entry plus this.
        pub grid_section: u32,
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
        /// Non-zero when `projection` is orthographic: the tiles' frustums have parallel sides,
        /// and their view-space boxes the same `xy` extent at every depth (`light_grid`'s
        /// `tile_rays`).
        pub orthographic: u32,
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
    /// Item types with lists of their own in every cell: lights, then decals.
    pub const ITEM_TYPES: u32 = 2;

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
    #[storage(group = 0, binding = 9)]
    static BOXES: [CullBox];

    /// Per list `j`, its light count at `j` and its decal count at `MAX_LISTS + j`.
    #[workgroup]
    static LIST_COUNT: [Atomic<u32>; ITEM_TYPES * MAX_LISTS];
    #[workgroup]
    static LIST_BASE: [u32; ITEM_TYPES * MAX_LISTS];
    #[workgroup]
    static LIST_ROOM: u32;
    /// Light hits cached from the front of `HITS`.
    #[workgroup]
    static HIT_COUNT: Atomic<u32>;
    /// Decal hits cached from the back of `HITS` (`HITS[MAX_HITS − 1 − h]`).
    #[workgroup]
    static BOX_HIT_COUNT: Atomic<u32>;
    #[workgroup]
    static HITS: [UVec2; MAX_HITS];
    /// The workgroup's tile's `TILE_DEPTH` entry, shared by `tile_bounds`.
    #[workgroup]
    static TILE_BOUNDS: UVec4;

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

    /// Whether `item` is a box (decal) rather than a sphere (light).
    fn is_box(item: u32) -> bool {
        item >= PARAMS.first_box
    }

    /// Box item `item`'s box in view space.
    fn view_box(item: u32) -> ViewBox {
        let b = BOXES[item - PARAMS.first_box];
        ViewBox {
            center: (PARAMS.view * b.center.xyz().extend(1.0)).xyz(),
            x: (PARAMS.view * b.axis_x.xyz().extend(0.0)).xyz(),
            y: (PARAMS.view * b.axis_y.xyz().extend(0.0)).xyz(),
            z: (PARAMS.view * b.axis_z.xyz().extend(0.0)).xyz(),
        }
    }

    /// Tile `tile`'s `TILE_DEPTH` entry, the same value in every invocation to WGSL's
    /// uniformity analysis too: a read of a `read_write` buffer may differ between invocations
    /// as far as the analysis knows, and the kernels return early and run barriers on these
    /// bounds. Invocation 0 (`lid`) reads it, and `uniform_load()` shares it. Every invocation
    /// of the workgroup calls it.
    fn tile_bounds(lid: u32, tile: u32) -> UVec4 {
        if lid == 0u32 {
            TILE_BOUNDS = TILE_DEPTH[tile];
        }
        TILE_BOUNDS.uniform_load()
    }

    /// Zeroes the per-list counters and the hit cache; invocations `0..ITEM_TYPES · MAX_LISTS`
    /// call it (the kernels' workgroups are that large), before a barrier.
    fn lists_reset(lid: u32) {
        if lid < ITEM_TYPES * MAX_LISTS {
            LIST_COUNT[lid].store(0u32);
        }
        if lid == 0u32 {
            HIT_COUNT.store(0u32);
            BOX_HIT_COUNT.store(0u32);
        }
    }

    /// Counting phase: counts `item` in the lists of `bits` and keeps it, with its bits, in the
    /// hit cache while there is room (lights from the front, boxes from the back).
    fn hit_add(bits: u32, item: u32) {
        if bits != 0u32 {
            list_add(bits, item, 0u32);
            if is_box(item) {
                let h = BOX_HIT_COUNT.fetch_add(1u32);
                if h < MAX_HITS {
                    HITS[MAX_HITS - 1u32 - h] = UVec2::new(item, bits);
                }
            } else {
                let h = HIT_COUNT.fetch_add(1u32);
                if h < MAX_HITS {
                    HITS[h] = UVec2::new(item, bits);
                }
            }
        }
    }

    /// Writing phase from the hit cache (after `lists_allocate` and a barrier), spread over
    /// `threads` invocations. Lights take slots in arrival order; each box takes its rank among
    /// the tile's boxes of the same list, so decal lists come out in item (layer) order.
    /// Returns `false`, writing nothing, when the hits did not fit: the caller then classifies
    /// its candidates again with `list_add(.., 1)` and orders the decal lists with
    /// `box_lists_order`.
    fn hits_write(lid: u32, threads: u32) -> bool {
        let n = HIT_COUNT.load();
        let boxes = BOX_HIT_COUNT.load();
        let fits = n <= MAX_HITS && boxes <= MAX_HITS - n;
        if fits {
            let mut i = lid;
            while i < n {
                let h = HITS[i];
                list_add(h.y, h.x, 1u32);
                i += threads;
            }
            let mut i = lid;
            while i < boxes {
                box_write_ranked(HITS[MAX_HITS - 1u32 - i], boxes);
                i += threads;
            }
        }
        fits
    }

    /// Writes the cached box hit `hit` into each of its lists at its rank there: the number of
    /// the tile's `boxes` cached box hits in that list with a smaller item.
    fn box_write_ranked(hit: UVec2, boxes: u32) {
        let mut rest = hit.y;
        while rest != 0u32 {
            let j = rest.trailing_zeros();
            rest = rest & (rest - 1u32);
            let bit = 1u32 << j;
            let mut rank = 0u32;
            for k in 0u32..boxes {
                let other = HITS[MAX_HITS - 1u32 - k];
                if (other.y & bit) != 0u32 && other.x < hit.x {
                    rank += 1u32;
                }
            }
            if LIST_ROOM != 0u32 {
                INDICES[LIST_BASE[MAX_LISTS + j] + rank] = hit.x - PARAMS.first_box;
            }
        }
    }

    /// Phase 0 counts `item` in every list of `bits` (its type's lists); phase 1 writes it
    /// there, a light as its item index, a box as its decal index (`bits` 0: nothing).
    fn list_add(bits: u32, item: u32, phase: u32) {
        let mut first = 0u32;
        let mut entry = item;
        if is_box(item) {
            first = MAX_LISTS;
            entry = item - PARAMS.first_box;
        }
        let mut rest = bits;
        while rest != 0u32 {
            let j = first + rest.trailing_zeros();
            rest = rest & (rest - 1u32);
            let slot = LIST_COUNT[j].fetch_add(1u32);
            if phase == 1u32 && LIST_ROOM != 0u32 {
                INDICES[LIST_BASE[j] + slot] = entry;
            }
        }
    }

    /// After the write phase, in uniform control flow, spread over `threads` invocations: a
    /// tile that wrote without the hit cache put its decal entries in arrival order, so each of
    /// its decal lists is sorted in place (odd-even transposition: one round per entry, each
    /// round's compare-swaps spread over the workgroup). A tile that wrote from the cache
    /// counted no decal entry in the write phase (`box_write_ranked` places them by rank), so
    /// its lists are left as they are. Nothing to do in frames without boxes.
    fn box_lists_order(lid: u32, lists: u32, threads: u32) {
        if PARAMS.first_box < PARAMS.item_count {
            workgroup_barrier();
            storage_barrier();
            // Loads every invocation shares (`uniform_load`): the rounds below hold barriers,
            // so their count must be uniform to WGSL's analysis, not only in fact.
            let room = LIST_ROOM.uniform_load();
            for j in 0u32..lists {
                let base = LIST_BASE[MAX_LISTS + j];
                let n = LIST_COUNT[MAX_LISTS + j].uniform_load() * room;
                for round in 0u32..n {
                    let mut p = 2u32 * lid + (round & 1u32);
                    while p + 1u32 < n {
                        let lo = INDICES[base + p];
                        let hi = INDICES[base + p + 1u32];
                        if lo > hi {
                            INDICES[base + p] = hi;
                            INDICES[base + p + 1u32] = lo;
                        }
                        p += 2u32 * threads;
                    }
                    storage_barrier();
                }
            }
        }
    }

    /// Between the phases (invocation 0, after a barrier): one global allocation for the `lists`
    /// lists of tile `tile` of every item type, their grid entries, and the counters reset for
    /// the write phase. A list's decals follow its lights in `INDICES`. A tile whose lists do
    /// not fit the index list gets empty lists; its entries are counted as dropped.
    fn lists_allocate(tile: u32, lists: u32) {
        let tile_count = PARAMS.tiles.x * PARAMS.tiles.y;
        let mut total = 0u32;
        let mut longest = 0u32;
        for j in 0u32..lists {
            let n = LIST_COUNT[j].load();
            let boxes = LIST_COUNT[MAX_LISTS + j].load();
            total += n + boxes;
            longest = longest.max(n).max(boxes);
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
            let boxes = LIST_COUNT[MAX_LISTS + j].load();
            let cell = tile + j * tile_count;
            LIST_BASE[j] = base;
            LIST_BASE[MAX_LISTS + j] = base + n;
            GRID[cell] = UVec2::new(base, n * room);
            GRID[cell + PARAMS.grid_section] = UVec2::new(base + n, boxes * room);
            base += n + boxes;
            LIST_COUNT[j].store(0u32);
            LIST_COUNT[MAX_LISTS + j].store(0u32);
        }
        LIST_ROOM = room;
    }

    /// Empty lists `0..lists` of every item type for tile `tile` (invocation 0).
    fn lists_clear(tile: u32, lists: u32) {
        let tile_count = PARAMS.tiles.x * PARAMS.tiles.y;
        for j in 0u32..lists {
            GRID[tile + j * tile_count] = UVec2::new(0u32, 0u32);
            GRID[tile + j * tile_count + PARAMS.grid_section] = UVec2::new(0u32, 0u32);
        }
    }
}
