//! Culling shadow casters on the GPU, per atlas region: which casters each region drawn this
//! frame receives, written straight into the indirect arguments its caster draws read.

/// Culls the scene's casters for a frame's shadow work: one invocation per caster slot, which
/// loads its caster once and tests it against every work item of the chunk in turn (the
/// items' region volumes are the same for every invocation, so they stay in cache), so the
/// casters are read once per chunk, not once per region.
///
/// A work item is one region's draw into one atlas: its static casters into the static cache,
/// its dynamic casters over the copied static depth, or every caster (uncached). The host
/// lays the casters out once in slots (`SLOTS`: the geometry's index range and base vertex,
/// and the draw, opaque casters first, then masked ones, each part with spare slots for
/// instances an engine adds); a work item's slots are its own run of `stride` indirect
/// arguments (five words each) and cast records (draw and region view, read by
/// `shadow_caster` through the instance index, which is the run's position).
///
/// A slot is drawn when it holds a draw, the draw casts (its box in `BOXES` is not empty:
/// blended draws and removed instances have empty boxes), it belongs to the work's casters
/// (`min.w`: 1 for a dynamic instance) and its box reaches the region: inside every plane of
/// the region's clip volume and overlapping the volume's world box where it has one
/// (`REGIONS`), the same test the CPU uses to tell which regions a moved caster touches. With
/// `cull` 0 every caster of the work is drawn. `COUNTS[0]` counts the casts drawn.
///
/// With `compact` (a device that draws a count read from a buffer), the drawn casts are packed
/// at the start of their part of the run, in no particular order (depth-only drawing keeps the
/// nearest depth whatever the order), and `COUNTS[1 + 2w]` and `COUNTS[2 + 2w]` count work
/// item `w`'s opaque and masked ones: the draws read only those, so a region costs what
/// reaches it. Without, every slot is written, with no instance where it is not drawn.
///
/// A device may bound a dispatch's arguments, so the host splits a frame's work into chunks:
/// `first_work` is the chunk's first work item, and its runs start at 0.
#[shader_dsl::shader(uses(crate::shared::box_frustum))]
pub mod shadow_cull {
    pub const WORKGROUP: u32 = 64;
    /// A slot without a draw.
    pub const NO_DRAW: u32 = 0xFFFF_FFFF;
    /// Which casters a work item draws.
    pub const ALL_CASTERS: u32 = 0;
    pub const STATIC_CASTERS: u32 = 1;
    pub const DYNAMIC_CASTERS: u32 = 2;

    /// One dispatch's share of the frame's work.
    pub struct ShadowCullParams {
        /// Slots per work item (the length of every run).
        pub stride: u32,
        /// The chunk's first work item in `WORK`.
        pub first_work: u32,
        /// Work items in the chunk.
        pub work_count: u32,
        /// 0: every caster of the work draws (culling off).
        pub cull: u32,
        /// Slots of the opaque part (the masked part follows).
        pub opaque: u32,
        /// 1: drawn casts packed and counted per part (see the module).
        pub compact: u32,
        pub pad0: u32,
        pub pad1: u32,
    }

    /// A caster slot: the draw's geometry and the draw.
    pub struct CasterSlot {
        pub index_count: u32,
        pub first_index: u32,
        /// The base vertex's bits (an `i32` in the indirect arguments).
        pub base_vertex: u32,
        /// The draw (`DRAWS` and `BOXES` index), or `NO_DRAW`.
        pub draw: u32,
    }

    /// A region's clip volume in world space.
    pub struct RegionVolume {
        pub frustum: Frustum,
        /// The volume's world box; `min.w` is 1 where the volume has one (0: it reaches
        /// infinity).
        pub min: Vec4,
        pub max: Vec4,
    }

    /// One region's draw into one atlas.
    pub struct ShadowWork {
        /// The region: its index in `REGIONS` and in the casters' `VIEWS`.
        pub view: u32,
        /// `ALL_CASTERS`, `STATIC_CASTERS` or `DYNAMIC_CASTERS`.
        pub casters: u32,
        pub pad0: u32,
        pub pad1: u32,
    }

    #[uniform(group = 0, binding = 0)]
    static PARAMS: ShadowCullParams;
    #[storage(group = 0, binding = 1)]
    static BOXES: [DrawBox];
    #[storage(group = 0, binding = 2)]
    static SLOTS: [CasterSlot];
    #[storage(group = 0, binding = 3)]
    static REGIONS: [RegionVolume];
    #[storage(group = 0, binding = 4)]
    static WORK: [ShadowWork];
    #[storage(group = 0, binding = 5, read_write)]
    static ARGS: [u32];
    #[storage(group = 0, binding = 6, read_write)]
    static CASTS: [u32];
    #[storage(group = 0, binding = 7, read_write)]
    static COUNTS: [Atomic<u32>];

    /// Whether `b` (not empty) reaches `region`'s clip volume.
    fn reaches_region(region: RegionVolume, b: DrawBox) -> bool {
        let bounded = region.min.w > 0.5;
        let overlaps = !bounded
            || (b.min.x <= region.max.x
                && b.min.y <= region.max.y
                && b.min.z <= region.max.z
                && b.max.x >= region.min.x
                && b.max.y >= region.min.y
                && b.max.z >= region.min.z);
        overlaps && draw_in_frustum(region.frustum, b, 0.0)
    }

    /// Writes cast `cast`: slot `s`'s geometry drawn `instances` times (0 or 1) as instance
    /// `cast`, and its record (the draw and the region view).
    fn write_cast(cast: u32, s: CasterSlot, view: u32, instances: u32) {
        let at = cast * 5u32;
        ARGS[at] = s.index_count;
        ARGS[at + 1u32] = instances;
        ARGS[at + 2u32] = s.first_index;
        ARGS[at + 3u32] = s.base_vertex;
        ARGS[at + 4u32] = cast;
        CASTS[cast * 2u32] = s.draw;
        CASTS[cast * 2u32 + 1u32] = view;
    }

    /// One caster slot against every work item of the chunk: its arguments and cast records.
    #[compute(workgroup_size(64, 1, 1))]
    pub fn cull_casters(#[builtin(global_invocation_id)] gid: UVec3) {
        let slot = gid.x;
        if slot < PARAMS.stride {
            let s = SLOTS[slot];
            let mut b = DrawBox {
                min: Vec4::ONE,
                max: Vec4::ZERO,
            };
            if s.draw != NO_DRAW {
                b = BOXES[s.draw];
            }
            // Empty boxes (and empty slots) cast nothing.
            let casts = b.min.x <= b.max.x;
            let dynamic = b.min.w > 0.5;
            let masked = slot >= PARAMS.opaque;
            let part = select(masked, 1u32, 0u32);
            let start = select(masked, PARAMS.opaque, 0u32);
            let mut drawn_count = 0u32;
            for run in 0u32..PARAMS.work_count {
                let w = PARAMS.first_work + run;
                let work = WORK[w];
                let wanted = work.casters == ALL_CASTERS
                    || (work.casters == STATIC_CASTERS && !dynamic)
                    || (work.casters == DYNAMIC_CASTERS && dynamic);
                let drawn = casts
                    && wanted
                    && (PARAMS.cull == 0u32 || reaches_region(REGIONS[work.view], b));
                if PARAMS.compact == 0u32 {
                    let instances = select(drawn, 1u32, 0u32);
                    write_cast(run * PARAMS.stride + slot, s, work.view, instances);
                } else if drawn {
                    let k = COUNTS[1u32 + 2u32 * w + part].fetch_add(1);
                    write_cast(run * PARAMS.stride + start + k, s, work.view, 1u32);
                }
                drawn_count = drawn_count + select(drawn, 1u32, 0u32);
            }
            if drawn_count > 0u32 {
                COUNTS[0].fetch_add(drawn_count);
            }
        }
    }
}
