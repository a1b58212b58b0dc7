// Golden: `u64` scalars and the visibility buffer's 64-bit atomic minimum, as a compute
// rasteriser writes it: depth bits over a triangle ID in one `Atomic<u64>` per pixel.
#[shader_dsl::shader(axes(far: bool = [false, true] => "far"))]
pub mod atomic_u64 {
    pub struct Fragment {
        pub depth: f32,
        pub id: u32,
        pub packed: u64,
    }

    /// The value a cleared pixel holds: nothing is nearer than everything.
    pub const CLEARED: u64 = u64::MAX;
    const ID_BITS: u32 = 32;
    const ID_MASK: u64 = (1u64 << ID_BITS) - 1u64;

    #[storage(group = 0, binding = 0)]
    static FRAGMENTS: [Fragment];
    #[storage(group = 0, binding = 1, read_write)]
    static VIS64: [Atomic<u64>];
    #[storage(group = 0, binding = 2, read_write)]
    static IDS: [u32];

    fn pack(depth: f32, id: u32) -> u64 {
        ((depth.to_bits() as u64) << ID_BITS) | (id as u64)
    }

    #[compute(workgroup_size(64, 1, 1))]
    pub fn raster(#[builtin(global_invocation_id)] gid: UVec3) {
        let f = FRAGMENTS[gid.x];
        let packed = pack(f.depth, f.id);
        let pixel = gid.x % 16u32;
        if far {
            VIS64[pixel].fetch_max(packed);
        } else {
            VIS64[pixel].fetch_min(packed);
        }
        let _ = VIS64[pixel].fetch_min(f.packed.max(packed) >> (gid.y & 63u32));
        if f.packed != CLEARED && f.packed & ID_MASK < 5000000000u64 {
            IDS[gid.x] = (f.packed & ID_MASK) as u32 + (f.packed >> 32u32) as u32;
        }
        let offset = ((f.id as i32) - 2) as u64 + (-2 as i32 as u64) + 3;
        IDS[gid.x + 1u32] = (offset as f32 + (f.packed as f32)) as u32;
    }
}
