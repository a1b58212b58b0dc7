// Golden: storage textures (write, read, read_write), texture loads with levels and layers,
// dimensions, and workgroup atomics on an array.
#[shader_dsl::shader]
pub mod storage_textures {
    #[texture(group = 0, binding = 0)]
    static SRC: Texture2d<f32>;
    #[texture(group = 0, binding = 1)]
    static SRC_ARRAY: Texture2dArray<f32>;
    #[texture(group = 0, binding = 2)]
    static DST: StorageTexture2d<Rgba8Unorm, Write>;
    #[texture(group = 0, binding = 3)]
    static HIST: StorageTexture2d<R32Uint, ReadWrite>;
    #[texture(group = 0, binding = 4)]
    static RO: StorageTexture2d<Rgba16Float, Read>;
    #[texture(group = 0, binding = 5)]
    static MS: TextureMultisampled2d<f32>;
    #[workgroup]
    static BINS: [Atomic<u32>; 16];

    #[compute(workgroup_size(8, 8))]
    pub fn main(#[builtin(global_invocation_id)] gid: UVec3, #[builtin(local_invocation_index)] lid: u32) {
        let dims = DST.dimensions();
        if gid.x >= dims.x || gid.y >= dims.y {
            return;
        }
        let p = gid.xy();
        let a = SRC.load(p, 0u32);
        let b = SRC_ARRAY.load(p, 1u32, 0u32);
        let c = RO.load(p);
        let d = MS.load(p, 3u32);
        let levels = SRC.num_levels() + SRC_ARRAY.num_layers() + MS.num_samples();
        let luma = (a.xyz() + b.xyz() + c.xyz() + d.xyz()).dot(Vec3::new(0.299, 0.587, 0.114));
        let bin = (luma.clamp(0.0, 1.0) * 15.0) as u32;
        BINS[bin].fetch_add(1u32);
        workgroup_barrier();
        if lid < 16u32 {
            let old = HIST.load(Vec2::new(lid as f32, 0.0).as_uvec2()).x;
            HIST.store(UVec2::new(lid, 0u32), UVec4::new(old + BINS[lid].load(), 0u32, 0u32, levels));
        }
        storage_barrier();
        DST.store(p, Vec4::new(luma, luma, luma, 1.0));
    }
}
