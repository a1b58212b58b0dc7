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
/// kernel, with the same overflow counters.
#[shader_dsl::shader(
    axes(
        msaa: u32 = [1, 2, 4, 8],
        scalarize: bool = [false, true] => "scalar",
    ),
    requires(subgroup = scalarize),
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

    /// An item's bounding sphere in world space.
    pub struct CullSphere {
        pub center: Vec3,
        pub radius: f32,
    }

    pub const MAX_PER_CLUSTER: u32 = 1024;
    pub const WORKGROUP: u32 = 64;
    pub const NEXT_INDEX: u32 = 0;
    pub const OVERFLOW_CLUSTERS: u32 = 1;
    pub const DROPPED: u32 = 2;
    pub const MAX_CLUSTER_ITEMS: u32 = 3;
    pub const COUNTER_COUNT: u32 = 4;
    /// Stands for infinity in plane distances (WGSL has no infinite literal).
    const FAR_AWAY: f32 = 3.0e38;

    #[uniform(group = 0, binding = 0)]
    static PARAMS: ClusterParams;
    #[storage(group = 0, binding = 1)]
    static ITEMS: [CullSphere];
    #[storage(group = 0, binding = 2, read_write)]
    static GRID: [UVec2];
    #[storage(group = 0, binding = 3, read_write)]
    static INDICES: [u32];
    #[storage(group = 0, binding = 4, read_write)]
    static COUNTERS: [Atomic<u32>];
    #[storage(group = 0, binding = 5, read_write)]
    static OCCUPIED: [u32];
    #[texture(group = 0, binding = 6)]
    #[when(msaa == 1)]
    static DEPTH: TextureDepth2d;
    #[texture(group = 0, binding = 6)]
    #[when(msaa > 1)]
    static DEPTH_MS: TextureDepthMultisampled2d;

    #[workgroup]
    static CLUSTER_COUNT: Atomic<u32>;
    #[workgroup]
    static CLUSTER_LIST: [u32; MAX_PER_CLUSTER];
    #[workgroup]
    static CLUSTER_BASE: u32;
    #[workgroup]
    static CLUSTER_STORED: u32;

    /// View depth (distance along −Z) of a depth-buffer value.
    fn view_depth(d: f32) -> f32 {
        let p = PARAMS.inv_projection * Vec4::new(0.0, 0.0, d, 1.0);
        -p.z / p.w
    }

    /// The depth slice of view depth `d`.
    fn slice_of(d: f32) -> u32 {
        let t = (d / PARAMS.near).ln() / (PARAMS.far / PARAMS.near).ln();
        let k = (t * PARAMS.grid.z as f32).floor().max(0.0);
        (k as u32).min(PARAMS.grid.z - 1u32)
    }

    /// View depth where slice `k` starts.
    fn slice_start(k: u32) -> f32 {
        let mut d = 0.0;
        if k >= PARAMS.grid.z {
            d = FAR_AWAY;
        } else if k > 0u32 {
            d = PARAMS.near * (PARAMS.far / PARAMS.near).powf(k as f32 / PARAMS.grid.z as f32);
        }
        d
    }

    /// The froxel column (or row) of pixel `x` when `count` columns share `size` pixels.
    fn column_of(x: u32, count: u32, size: u32) -> u32 {
        ((x + 1u32) * count - 1u32) / size
    }

    /// Flags the froxel of every surface sample.
    #[compute(workgroup_size(8, 8, 1))]
    pub fn mark_occupied(#[builtin(global_invocation_id)] gid: UVec3) {
        if gid.x < PARAMS.screen.x && gid.y < PARAMS.screen.y {
            let i = column_of(gid.x, PARAMS.grid.x, PARAMS.screen.x);
            let j = column_of(gid.y, PARAMS.grid.y, PARAMS.screen.y);
            for s in 0u32..msaa {
                let mut d = 1.0;
                if msaa == 1 {
                    d = DEPTH.load(gid.xy(), 0u32);
                } else {
                    d = DEPTH_MS.load(gid.xy(), s);
                }
                if d < 1.0 {
                    let k = slice_of(view_depth(d));
                    OCCUPIED[(k * PARAMS.grid.y + j) * PARAMS.grid.x + i] = 1u32;
                }
            }
        }
    }

    /// A plane from a combination of projection rows, normalised.
    fn normalized_plane(v: Vec4) -> Vec4 {
        v / v.xyz().length()
    }

    /// Whether a view-space sphere clears all six froxel planes.
    fn sphere_in_froxel(
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
            CLUSTER_COUNT.store(0u32);
        }
        workgroup_barrier();

        // Froxel planes: pixel-edge sides from the projection rows, slice bounds in depth.
        let m = PARAMS.projection;
        let row0 = Vec4::new(m.x_axis.x, m.y_axis.x, m.z_axis.x, m.w_axis.x);
        let row1 = Vec4::new(m.x_axis.y, m.y_axis.y, m.z_axis.y, m.w_axis.y);
        let row3 = Vec4::new(m.x_axis.w, m.y_axis.w, m.z_axis.w, m.w_axis.w);
        let size = PARAMS.screen.as_vec2();
        let px0 = (wg.x * PARAMS.screen.x / grid.x) as f32;
        let px1 = ((wg.x + 1u32) * PARAMS.screen.x / grid.x) as f32;
        let py0 = (wg.y * PARAMS.screen.y / grid.y) as f32;
        let py1 = ((wg.y + 1u32) * PARAMS.screen.y / grid.y) as f32;
        let x0 = 2.0 * px0 / size.x - 1.0;
        let x1 = 2.0 * px1 / size.x - 1.0;
        let y1 = 1.0 - 2.0 * py0 / size.y;
        let y0 = 1.0 - 2.0 * py1 / size.y;
        let left = normalized_plane(row0 - x0 * row3);
        let right = normalized_plane(x1 * row3 - row0);
        let bottom = normalized_plane(row1 - y0 * row3);
        let top = normalized_plane(y1 * row3 - row1);
        let near = slice_start(wg.z);
        let far = slice_start(wg.z + 1u32);

        let rounds = (PARAMS.item_count + WORKGROUP - 1u32) / WORKGROUP;
        for round in 0u32..rounds {
            let item = round * WORKGROUP + lid;
            let mut visible = false;
            if item < PARAMS.item_count {
                let sphere = ITEMS[item];
                let c = (PARAMS.view
                    * Vec4::new(sphere.center.x, sphere.center.y, sphere.center.z, 1.0))
                .xyz();
                visible = sphere_in_froxel(c, sphere.radius, left, right, bottom, top, near, far);
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
                        base = CLUSTER_COUNT.fetch_add(total);
                    }
                    base = subgroup_broadcast_first(base);
                    let slot = base + rank;
                    if visible && slot < PARAMS.max_per_cluster {
                        CLUSTER_LIST[slot] = item;
                    }
                }
            } else {
                if visible {
                    let slot = CLUSTER_COUNT.fetch_add(1u32);
                    if slot < PARAMS.max_per_cluster {
                        CLUSTER_LIST[slot] = item;
                    }
                }
            }
        }
        workgroup_barrier();

        if lid == 0u32 {
            let found = CLUSTER_COUNT.load();
            let kept = found.min(PARAMS.max_per_cluster);
            COUNTERS[MAX_CLUSTER_ITEMS].fetch_max(found);
            if found > kept {
                COUNTERS[OVERFLOW_CLUSTERS].fetch_add(1u32);
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
            CLUSTER_BASE = offset;
            CLUSTER_STORED = stored;
            GRID[cluster] = UVec2::new(offset, stored);
        }
        workgroup_barrier();
        let base = CLUSTER_BASE;
        let stored = CLUSTER_STORED;
        let mut j = lid;
        while j < stored {
            INDICES[base + j] = CLUSTER_LIST[j];
            j += WORKGROUP;
        }
    }
}
