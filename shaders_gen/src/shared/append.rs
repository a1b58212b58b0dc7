//! The output side of the culling kernels: gathering a cell's surviving items in workgroup
//! memory and appending them to the global index list, with the overflow counters.

/// The `(offset, count)` grid, the index list and the counters both culling kernels write
/// (group 0, bindings 2, 3 and 4), the items they read (binding 1), and the two steps that fill
/// the lists: `gather` (each invocation offers one item per round) and `store_list` (one global
/// allocation per cell, then a parallel copy).
///
/// Capacities are runtime parameters (`max_per_cell` up to [`MAX_PER_CELL`],
/// `index_capacity`); anything that does not fit is counted in `COUNTERS`, never written out of
/// bounds. With `scalarize`, survivors are appended with a ballot and an exclusive add, one
/// workgroup atomic per subgroup instead of one per survivor.
#[shader_dsl::library(
    axes(scalarize: bool = [false, true]),
    requires(subgroup = scalarize),
)]
pub mod cull_append {
    /// An item's bounding sphere in world space.
    pub struct CullSphere {
        pub center: Vec3,
        pub radius: f32,
    }

    /// Largest per-cell list a workgroup can gather (workgroup memory).
    pub const MAX_PER_CELL: u32 = 1024;
    /// `COUNTERS[NEXT_INDEX]`: entries allocated in `INDICES` (may exceed the capacity).
    pub const NEXT_INDEX: u32 = 0;
    /// `COUNTERS[OVERFLOW_CELLS]`: cells that found more items than their `max_per_cell`.
    pub const OVERFLOW_CELLS: u32 = 1;
    /// `COUNTERS[DROPPED]`: list entries dropped for lack of room (per cell or in total).
    pub const DROPPED: u32 = 2;
    /// `COUNTERS[MAX_CELL_ITEMS]`: the most items any cell found.
    pub const MAX_CELL_ITEMS: u32 = 3;
    /// Number of counters.
    pub const COUNTER_COUNT: u32 = 4;

    #[storage(group = 0, binding = 1)]
    static ITEMS: [CullSphere];
    #[storage(group = 0, binding = 2, read_write)]
    static GRID: [UVec2];
    #[storage(group = 0, binding = 3, read_write)]
    static INDICES: [u32];
    #[storage(group = 0, binding = 4, read_write)]
    static COUNTERS: [Atomic<u32>];

    #[workgroup]
    static CELL_COUNT: Atomic<u32>;
    #[workgroup]
    static CELL_LIST: [u32; MAX_PER_CELL];
    #[workgroup]
    static CELL_BASE: u32;
    #[workgroup]
    static CELL_STORED: u32;

    /// Empties the workgroup's list; one invocation calls it, before a barrier.
    fn gather_reset() {
        CELL_COUNT.store(0u32);
    }

    /// Appends `item` to the workgroup's list when `visible` (slots past `max_per_cell` are
    /// counted, not written). Every invocation of the workgroup calls it in uniform control flow.
    fn gather(visible: bool, item: u32, lane: u32, max_per_cell: u32) {
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
                    base = CELL_COUNT.fetch_add(total);
                }
                base = subgroup_broadcast_first(base);
                let slot = base + rank;
                if visible && slot < max_per_cell {
                    CELL_LIST[slot] = item;
                }
            }
        } else {
            if visible {
                let slot = CELL_COUNT.fetch_add(1u32);
                if slot < max_per_cell {
                    CELL_LIST[slot] = item;
                }
            }
        }
    }

    /// After the gather: one global allocation for grid cell `cell` (invocation 0), overflow
    /// counted, never written; then the workgroup's `threads` invocations copy the list out.
    fn store_list(cell: u32, lid: u32, threads: u32, max_per_cell: u32, index_capacity: u32) {
        workgroup_barrier();
        if lid == 0u32 {
            let found = CELL_COUNT.load();
            let kept = found.min(max_per_cell);
            COUNTERS[MAX_CELL_ITEMS].fetch_max(found);
            if found > kept {
                COUNTERS[OVERFLOW_CELLS].fetch_add(1u32);
            }
            let offset = COUNTERS[NEXT_INDEX].fetch_add(kept);
            let mut room = 0u32;
            if offset < index_capacity {
                room = index_capacity - offset;
            }
            let stored = kept.min(room);
            if found > stored {
                COUNTERS[DROPPED].fetch_add(found - stored);
            }
            CELL_BASE = offset;
            CELL_STORED = stored;
            GRID[cell] = UVec2::new(offset, stored);
        }
        workgroup_barrier();
        let base = CELL_BASE;
        let stored = CELL_STORED;
        let mut j = lid;
        while j < stored {
            INDICES[base + j] = CELL_LIST[j];
            j += threads;
        }
    }
}
