//! Clustered light culling: screen tiles × exponential depth slices (froxels), as in Olsson's
//! clustered shading, Bevy and DOOM 2016 (16×8×24).

/// Clustered culling over a runtime `grid` of froxels.
///
/// Froxel column `i` spans pixels `[i·w/X, (i+1)·w/X)` (integer division), and likewise for
/// rows, so every sample of a pixel lies inside its froxel's planes. Depth slice `k` spans view
/// depths `near·(far/near)^(k/Z)` to the next; slice 0 reaches the eye and the last slice goes to
/// infinity, so every surface belongs to some froxel.
///
/// `mark_occupied` (optional, one invocation per pixel) flags the froxels that hold a depth
/// sample; with `skip_empty` set, `cull` gives the other froxels empty lists. `cull` runs one
/// workgroup per froxel and writes the same `(offset, count)` grid and index list as the tiled
/// kernel, with the same overflow counters: the gather, the append, the output bindings and
/// the counters are the `cull_append` library's, the froxel geometry `light_grid`'s.
#[shader_dsl::shader(
    axes(
        msaa: u32 = [1, 2, 4, 8],
        scalarize: bool = [false, true] => "scalar",
    ),
    requires(subgroup = scalarize),
    uses(crate::shared::light_grid, crate::shared::cull_append),
)]
pub mod cluster_cull {
    /// Camera, grid and capacities of the clustered pass.
    pub struct ClusterParams {
        pub view: Mat4,
        pub projection: Mat4,
        pub inv_projection: Mat4,
        /// Target size in pixels.
        pub screen: UVec2,
        /// Froxels across, down and in depth.
        pub grid: UVec3,
        /// View depth where slice 1 starts.
        pub near: f32,
        /// View depth where the last slice starts.
        pub far: f32,
        pub item_count: u32,
        /// Most items one froxel may list (at most `MAX_PER_CLUSTER`).
        pub max_per_cluster: u32,
        /// Entries `INDICES` may hold.
        pub index_capacity: u32,
        /// Non-zero: froxels not flagged by `mark_occupied` get no items.
        pub skip_empty: u32,
    }

    /// Largest per-froxel list the workgroup can gather (workgroup memory).
    pub const MAX_PER_CLUSTER: u32 = MAX_PER_CELL;
    pub const WORKGROUP: u32 = 64;
    /// `COUNTERS[OVERFLOW_CLUSTERS]`: froxels that found more items than `max_per_cluster`.
    pub const OVERFLOW_CLUSTERS: u32 = OVERFLOW_CELLS;
    /// `COUNTERS[MAX_CLUSTER_ITEMS]`: the most items any froxel found.
    pub const MAX_CLUSTER_ITEMS: u32 = MAX_CELL_ITEMS;

    #[uniform(group = 0, binding = 0)]
    static PARAMS: ClusterParams;
    #[storage(group = 0, binding = 5, read_write)]
    static OCCUPIED: [u32];
    #[texture(group = 0, binding = 6)]
    #[when(msaa == 1)]
    static DEPTH: TextureDepth2d;
    #[texture(group = 0, binding = 6)]
    #[when(msaa > 1)]
    static DEPTH_MS: TextureDepthMultisampled2d;

    /// The depth slice of view depth `d`.
    fn slice_at(d: f32) -> u32 {
        slice_of(d, PARAMS.near, PARAMS.far, PARAMS.grid.z)
    }

    /// View depth where slice `k` starts.
    fn start_of(k: u32) -> f32 {
        slice_start(k, PARAMS.near, PARAMS.far, PARAMS.grid.z)
    }

    /// Flags the froxel of every surface sample.
    #[compute(workgroup_size(8, 8, 1))]
    pub fn mark_occupied(#[builtin(global_invocation_id)] gid: UVec3) {
        if gid.x < PARAMS.screen.x && gid.y < PARAMS.screen.y {
            for s in 0u32..msaa {
                let mut d = 1.0;
                if msaa == 1 {
                    d = DEPTH.load(gid.xy(), 0u32);
                } else {
                    d = DEPTH_MS.load(gid.xy(), s);
                }
                if d < 1.0 {
                    let k = slice_at(view_depth(PARAMS.inv_projection, d));
                    OCCUPIED[froxel_cell(gid.xy(), k, PARAMS.grid, PARAMS.screen)] = 1u32;
                }
            }
        }
    }

    #[compute(workgroup_size(64, 1, 1))]
    pub fn cull(
        #[builtin(local_invocation_index)] lid: u32,
        #[builtin(workgroup_id)] wg: UVec3,
        #[builtin(subgroup_invocation_id)] lane: u32,
    ) {
        let grid = PARAMS.grid;
        let cluster = (wg.z * grid.y + wg.y) * grid.x + wg.x;
        if PARAMS.skip_empty != 0u32 && OCCUPIED[cluster] == 0u32 {
            if lid == 0u32 {
                GRID[cluster] = UVec2::new(0u32, 0u32);
            }
            return;
        }
        if lid == 0u32 {
            gather_reset();
        }
        workgroup_barrier();

        // Froxel planes: pixel-edge sides from the projection rows, slice bounds in depth.
        let size = PARAMS.screen.as_vec2();
        let px0 = (wg.x * PARAMS.screen.x / grid.x) as f32;
        let px1 = ((wg.x + 1u32) * PARAMS.screen.x / grid.x) as f32;
        let py0 = (wg.y * PARAMS.screen.y / grid.y) as f32;
        let py1 = ((wg.y + 1u32) * PARAMS.screen.y / grid.y) as f32;
        let x0 = 2.0 * px0 / size.x - 1.0;
        let x1 = 2.0 * px1 / size.x - 1.0;
        let y1 = 1.0 - 2.0 * py0 / size.y;
        let y0 = 1.0 - 2.0 * py1 / size.y;
        let sides = side_planes(PARAMS.projection, x0, x1, y0, y1);
        let near = start_of(wg.z);
        let far = start_of(wg.z + 1u32);

        // The subgroup lane exists only in scalarized variants.
        let mut lane_id = 0u32;
        if scalarize {
            lane_id = lane;
        }
        let rounds = (PARAMS.item_count + WORKGROUP - 1u32) / WORKGROUP;
        for round in 0u32..rounds {
            let item = round * WORKGROUP + lid;
            let mut visible = false;
            if item < PARAMS.item_count {
                let sphere = ITEMS[item];
                let c = (PARAMS.view
                    * Vec4::new(sphere.center.x, sphere.center.y, sphere.center.z, 1.0))
                .xyz();
                visible = sphere_in_frustum(c, sphere.radius, sides, near, far);
            }
            gather(visible, item, lane_id, PARAMS.max_per_cluster);
        }
        store_list(
            cluster,
            lid,
            WORKGROUP,
            PARAMS.max_per_cluster,
            PARAMS.index_capacity,
        );
    }
}
