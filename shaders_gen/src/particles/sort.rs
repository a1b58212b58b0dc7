//! A bitonic sort of `(key, payload)` pairs on the GPU, ascending by key then payload: blended
//! particles' back-to-front order. Blocks of 512 are sorted in workgroup memory; each later
//! stage merges with global steps while the pairs are more than 512 apart, then finishes the
//! stage inside blocks again.

/// Bitonic sort kernels over `KEYS` (a power of two of at least [`particle_sort::BLOCK`] pairs;
/// pad with `u32::MAX` keys, which sort last).
///
/// The host runs `sort_local` once, then for each stage `k = 1024, 2048, .., n`: `merge_global`
/// for `j = k/2, .., 512` and `merge_local` with `k`.
#[shader_dsl::shader]
pub mod particle_sort {
    /// Threads per workgroup; each handles two pairs of a block.
    pub const WORKGROUP: u32 = 256;
    /// Pairs sorted in workgroup memory at once.
    pub const BLOCK: u32 = 512;

    /// The stage (`k`, the size of the sequences being merged) and step (`j`, the distance
    /// between compared pairs), and the number of pairs.
    pub struct SortParams {
        pub k: u32,
        pub j: u32,
        pub count: u32,
        pub pad: u32,
    }

    #[uniform(group = 0, binding = 0)]
    static PARAMS: SortParams;
    #[storage(group = 0, binding = 1, read_write)]
    static KEYS: [UVec2];
    #[workgroup]
    static BLOCK_KEYS: [UVec2; 512];

    /// Whether `a` sorts before `b`: by key, then by payload.
    fn before(a: UVec2, b: UVec2) -> bool {
        if a.x == b.x {
            return a.y < b.y;
        }
        a.x < b.x
    }

    /// Thread `t`'s compare-exchange of step `j` of stage `k` inside the block at `base`.
    fn exchange_local(t: u32, base: u32, k: u32, j: u32) {
        let i = 2u32 * j * (t / j) + t % j;
        let ascending = ((base + i) & k) == 0u32;
        let a = BLOCK_KEYS[i];
        let b = BLOCK_KEYS[i + j];
        if before(b, a) == ascending {
            BLOCK_KEYS[i] = b;
            BLOCK_KEYS[i + j] = a;
        }
    }

    fn load_block(t: u32, base: u32) {
        BLOCK_KEYS[t] = KEYS[base + t];
        BLOCK_KEYS[t + 256u32] = KEYS[base + t + 256u32];
        workgroup_barrier();
    }

    fn store_block(t: u32, base: u32) {
        KEYS[base + t] = BLOCK_KEYS[t];
        KEYS[base + t + 256u32] = BLOCK_KEYS[t + 256u32];
    }

    /// Every stage up to 512 inside each block (alternate blocks end up ascending and
    /// descending, ready for the stage of 1024).
    #[compute(workgroup_size(256, 1, 1))]
    pub fn sort_local(
        #[builtin(local_invocation_index)] t: u32,
        #[builtin(workgroup_id)] group: UVec3,
    ) {
        let base = group.x * 512u32;
        load_block(t, base);
        let mut k = 2u32;
        while k <= 512u32 {
            let mut j = k / 2u32;
            while j > 0u32 {
                exchange_local(t, base, k, j);
                workgroup_barrier();
                j = j / 2u32;
            }
            k = k * 2u32;
        }
        store_block(t, base);
    }

    /// Steps `j = 256, .., 1` of stage `PARAMS.k` inside each block.
    #[compute(workgroup_size(256, 1, 1))]
    pub fn merge_local(
        #[builtin(local_invocation_index)] t: u32,
        #[builtin(workgroup_id)] group: UVec3,
    ) {
        let base = group.x * 512u32;
        load_block(t, base);
        let mut j = 256u32;
        while j > 0u32 {
            exchange_local(t, base, PARAMS.k, j);
            workgroup_barrier();
            j = j / 2u32;
        }
        store_block(t, base);
    }

    /// Step `PARAMS.j` (at least 512) of stage `PARAMS.k`, in global memory.
    #[compute(workgroup_size(256, 1, 1))]
    pub fn merge_global(#[builtin(global_invocation_id)] gid: UVec3) {
        let t = gid.x;
        let j = PARAMS.j;
        if t < PARAMS.count / 2u32 {
            let i = 2u32 * j * (t / j) + t % j;
            let ascending = (i & PARAMS.k) == 0u32;
            let a = KEYS[i];
            let b = KEYS[i + j];
            if before(b, a) == ascending {
                KEYS[i] = b;
                KEYS[i + j] = a;
            }
        }
    }
}
