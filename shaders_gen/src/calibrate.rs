//! Kernels that measure a device's ceilings, so benchmarks can set their figures beside the
//! physical floor (`cargo xtask bench-cull --calibrate`).

/// An FMA-bound kernel: every invocation runs [`fma_rate::CHAINS`] independent multiply-add
/// chains for [`fma_rate::ITERATIONS`] steps (2 FLOP each) and stores their sum so nothing is
/// optimised away.
#[shader_dsl::shader]
pub mod fma_rate {
    pub const ITERATIONS: u32 = 4096;
    pub const CHAINS: u32 = 8;
    pub const WORKGROUP: u32 = 256;

    #[storage(group = 0, binding = 0, read_write)]
    static SINK: [f32];

    #[compute(workgroup_size(256, 1, 1))]
    pub fn fma_chains(#[builtin(global_invocation_id)] gid: UVec3) {
        let seed = gid.x as f32 * 0.000001;
        let mut a = seed;
        let mut b = seed + 0.1;
        let mut c = seed + 0.2;
        let mut d = seed + 0.3;
        let mut e = seed + 0.4;
        let mut f = seed + 0.5;
        let mut g = seed + 0.6;
        let mut h = seed + 0.7;
        for _i in 0u32..ITERATIONS {
            a = a * 0.9999 + 0.0001;
            b = b * 0.9999 + 0.0001;
            c = c * 0.9999 + 0.0001;
            d = d * 0.9999 + 0.0001;
            e = e * 0.9999 + 0.0001;
            f = f * 0.9999 + 0.0001;
            g = g * 0.9999 + 0.0001;
            h = h * 0.9999 + 0.0001;
        }
        SINK[gid.x] = a + b + c + d + e + f + g + h;
    }
}
