//! Sizing and placing particles in the lighting atlas, on the GPU. `size_particles` gives each
//! visible particle a square side from its projected size (a quarter of its screen width,
//! clamped to 2–32 texels, rounded up to a power of two), counts each side and writes the
//! back-to-front sort keys; `plan_atlas` (one thread) picks how much to shrink every side when
//! they do not all fit, and where each side's regions start; `allocate_regions` bumps each
//! particle's region out of its side's range with one atomic.
//!
//! Regions live in Morton (Z) order of 2×2-texel cells. A region of side `2^(c+1)` is `4^c`
//! consecutive cells starting at a multiple of `4^c`, so allocating the largest sides first
//! keeps every region square and aligned, and no two overlap.

/// Atlas sizing and allocation kernels (see the module docs).
///
/// `STATE` (`u32` atomics): `[0..5)` regions per side class, `[5..10)` allocation cursors,
/// `[10..15)` each class's first cell, `[15]` the shrink (classes dropped, 0 to 4), `[16]` cells
/// used, `[17]` visible particles, `[18]` frames that had to shrink (reported), `[19..24)` each
/// shrunk class's first entry in `OWNERS`.
///
/// `OWNERS` lists the slot of every region, class by class (largest first) in allocation
/// order, so a texel finds its particle from its cell alone (`particle_light`). `STATE` ends
/// with the frame's indirect arguments: `[24..28)` the billboard draw (6 vertices × visible
/// particles), `[28..31)` the lighting dispatch (`LIGHT_WORKGROUP` texels a workgroup, rows of
/// `LIGHT_ROW_GROUPS` workgroups).
#[shader_dsl::shader(uses(crate::particles::common::particle_common))]
pub mod particle_atlas {
    pub const WORKGROUP: u32 = 64;
    /// Side classes: sides 2, 4, 8, 16 and 32 texels.
    pub const CLASSES: u32 = 5;
    /// `REGIONS` entry of a particle outside the view.
    pub const HIDDEN: u32 = 0xFFFFFFFFu32;
    /// Texels a workgroup of `particle_light` lights.
    pub const LIGHT_WORKGROUP: u32 = 64;
    /// Workgroups in one row of the lighting dispatch.
    pub const LIGHT_ROW_GROUPS: u32 = 32768;

    pub struct AtlasParams {
        pub view: Mat4,
        /// Pixels per world unit at view depth 1 (`projection[1][1] · height / 2`), or at every
        /// depth for an orthographic camera.
        pub pixels_per_unit: f32,
        /// Particles nearer than this are not drawn.
        pub near: f32,
        /// Atlas side in 2×2 cells.
        pub cells_across: u32,
        /// Entries of `KEYS` (the sort's padded count).
        pub key_count: u32,
        /// Non-zero for an orthographic camera: screen size does not shrink with view depth.
        pub orthographic: u32,
    }

    #[uniform(group = 0, binding = 0)]
    static PARAMS: AtlasParams;
    #[storage(group = 0, binding = 1)]
    static EMITTERS: [GpuEmitter];
    #[storage(group = 0, binding = 2)]
    static PARTICLES: [GpuParticle];
    #[storage(group = 0, binding = 3)]
    static ALIVE: [u32];
    #[storage(group = 0, binding = 4, read_write)]
    static COUNTERS: [Atomic<i32>];
    #[storage(group = 0, binding = 5, read_write)]
    static KEYS: [UVec2];
    #[storage(group = 0, binding = 6, read_write)]
    static REGIONS: [u32];
    #[storage(group = 0, binding = 7, read_write)]
    static STATE: [Atomic<u32>];
    #[storage(group = 0, binding = 8, read_write)]
    static OWNERS: [u32];

    /// The side class (side `2 << class`) of a region for a particle `pixels` wide on screen.
    pub fn side_class(pixels: f32) -> u32 {
        let side = (pixels * 0.25).clamp(2.0, 32.0);
        let mut class = 0u32;
        while ((2u32 << class) as f32) < side {
            class = class + 1u32;
        }
        class
    }

    /// Per sort entry: a live, visible particle's class and key; `u32::MAX` keys elsewhere.
    #[compute(workgroup_size(64, 1, 1))]
    pub fn size_particles(#[builtin(global_invocation_id)] gid: UVec3) {
        let i = gid.x;
        if i < PARAMS.key_count {
            let alive = COUNTERS[1].load() as u32;
            let mut key = UVec2::new(u32::MAX, u32::MAX);
            if i < alive {
                let slot = ALIVE[i];
                let p = PARTICLES[slot];
                let depth = -(PARAMS.view * p.position.extend(1.0)).z;
                let mut region = HIDDEN;
                if depth > PARAMS.near {
                    let mut scale = depth;
                    if PARAMS.orthographic != 0u32 {
                        scale = 1.0;
                    }
                    let pixels =
                        2.0 * half_width(EMITTERS[p.emitter], p) * PARAMS.pixels_per_unit / scale;
                    let class = side_class(pixels);
                    STATE[class].fetch_add(1u32);
                    STATE[17].fetch_add(1u32);
                    region = class;
                    // Back to front: the farthest first (positive depths order as their bits).
                    key = UVec2::new(0xFFFFFFFEu32 - depth.to_bits(), slot);
                }
                REGIONS[slot] = region;
            }
            KEYS[i] = key;
        }
    }

    /// One thread: the smallest shrink that fits every region, and each class's first cell,
    /// largest sides first.
    #[compute(workgroup_size(1, 1, 1))]
    pub fn plan_atlas() {
        let capacity = PARAMS.cells_across * PARAMS.cells_across;
        let mut shrink = 0u32;
        let mut fits = false;
        while !fits {
            let mut total = 0u32;
            for c in 0u32..CLASSES {
                let shrunk = select(c > shrink, c - shrink, 0u32);
                total = total + STATE[c].load() * (1u32 << (2u32 * shrunk));
            }
            if total <= capacity || shrink == CLASSES - 1u32 {
                fits = true;
                STATE[16].store(total);
            } else {
                shrink = shrink + 1u32;
            }
        }
        STATE[15].store(shrink);
        if shrink > 0u32 {
            STATE[18].fetch_add(1u32);
        }
        // Regions per shrunk class, then bases (in cells and in `OWNERS`) from the largest
        // class down.
        let mut next = 0u32;
        let mut owners = 0u32;
        for step in 0u32..CLASSES {
            let target = CLASSES - 1u32 - step;
            let mut count = 0u32;
            for c in 0u32..CLASSES {
                let shrunk = select(c > shrink, c - shrink, 0u32);
                if shrunk == target {
                    count = count + STATE[c].load();
                }
            }
            STATE[10u32 + target].store(next);
            STATE[19u32 + target].store(owners);
            next = next + count * (1u32 << (2u32 * target));
            owners = owners + count;
        }
        let visible = STATE[17].load();
        STATE[24].store(6u32);
        STATE[25].store(visible);
        STATE[26].store(0u32);
        STATE[27].store(0u32);
        let groups = (STATE[16].load() * 4u32 + LIGHT_WORKGROUP - 1u32) / LIGHT_WORKGROUP;
        STATE[28].store(groups.min(LIGHT_ROW_GROUPS));
        STATE[29].store((groups + LIGHT_ROW_GROUPS - 1u32) / LIGHT_ROW_GROUPS);
        STATE[30].store(1u32);
    }

    /// Per live particle: its region, packed as `x | y << 12 | class << 24` (texels).
    #[compute(workgroup_size(64, 1, 1))]
    pub fn allocate_regions(#[builtin(global_invocation_id)] gid: UVec3) {
        let i = gid.x;
        let alive = COUNTERS[1].load() as u32;
        if i < alive {
            let slot = ALIVE[i];
            let class = REGIONS[slot];
            if class != HIDDEN {
                let shrink = STATE[15].load();
                let shrunk = select(class > shrink, class - shrink, 0u32);
                let at = STATE[5u32 + shrunk].fetch_add(1u32);
                let cell = STATE[10u32 + shrunk].load() + at * (1u32 << (2u32 * shrunk));
                let corner = morton_cell(cell) * 2u32;
                REGIONS[slot] = corner.x | (corner.y << 12u32) | (shrunk << 24u32);
                OWNERS[STATE[19u32 + shrunk].load() + at] = slot;
            }
        }
    }
}
