//! Kernels that copy frame data out for tools: the benchmark measures cull efficiency on depth
//! read back through [`depth_probe`]; the tests read a multisampled visibility buffer back
//! through [`sample_copy`].

/// Copies one depth sample from each point of a regular probe grid over the frame.
///
/// Probe `(i, j)` reads pixel `(i * stride + stride / 2, j * stride + stride / 2)` (clamped to
/// the screen) at sample `(i + j) % msaa`, and writes it to `PROBES[j * grid.x + i]`. A
/// multisampled depth buffer cannot be copied to a buffer directly, and the whole buffer is far
/// more than a statistic needs (3840×2160 at MSAA 8 is 265 MB).
#[shader_dsl::shader(axes(msaa: u32 = [1, 2, 4, 8]))]
pub mod depth_probe {
    /// Frame size and probe grid.
    pub struct ProbeParams {
        /// Frame size in pixels.
        pub screen: UVec2,
        /// Probes across and down.
        pub grid: UVec2,
        /// Pixels between probes.
        pub stride: u32,
    }

    /// Workgroup side: 8×8 probes per workgroup.
    pub const WORKGROUP_SIDE: u32 = 8;

    #[uniform(group = 0, binding = 0)]
    static PARAMS: ProbeParams;
    #[storage(group = 0, binding = 1, read_write)]
    static PROBES: [f32];
    #[texture(group = 0, binding = 2)]
    #[when(msaa == 1)]
    static DEPTH: TextureDepth2d;
    #[texture(group = 0, binding = 2)]
    #[when(msaa > 1)]
    static DEPTH_MS: TextureDepthMultisampled2d;

    #[compute(workgroup_size(8, 8, 1))]
    pub fn probe(#[builtin(global_invocation_id)] gid: UVec3) {
        if gid.x >= PARAMS.grid.x || gid.y >= PARAMS.grid.y {
            return;
        }
        let half = PARAMS.stride / 2u32;
        let x = (gid.x * PARAMS.stride + half).min(PARAMS.screen.x - 1u32);
        let y = (gid.y * PARAMS.stride + half).min(PARAMS.screen.y - 1u32);
        let p = UVec2::new(x, y);
        let mut d = 1.0;
        if msaa == 1 {
            d = DEPTH.load(p, 0u32);
        } else {
            d = DEPTH_MS.load(p, (gid.x + gid.y) % msaa);
        }
        PROBES[gid.y * PARAMS.grid.x + gid.x] = d;
    }
}

/// Copies every sample of a multisampled `u32` texture (the visibility buffer's triangle IDs),
/// or with `depth` of a multisampled depth texture (as the bits of each `f32`), into a buffer,
/// texel by texel, sample after sample: `SAMPLES[(y · width + x) · msaa + s]`. A multisampled
/// texture cannot be copied to a buffer directly; a tool that reads one back (the tests' host
/// replay of the visibility shading kernel) dispatches this over it.
#[shader_dsl::shader(axes(msaa: u32 = [2, 4, 8], depth: bool = [false, true]))]
pub mod sample_copy {
    #[storage(group = 0, binding = 0, read_write)]
    static SAMPLES: [u32];
    #[texture(group = 0, binding = 1)]
    #[when(!depth)]
    static SOURCE: TextureMultisampled2d<u32>;
    #[texture(group = 0, binding = 1)]
    #[when(depth)]
    static SOURCE_DEPTH: TextureDepthMultisampled2d;

    /// Copies the samples of texel `gid.xy` (8 × 8 texels a workgroup).
    #[compute(workgroup_size(8, 8, 1))]
    pub fn copy(#[builtin(global_invocation_id)] gid: UVec3) {
        let mut size = UVec2::ZERO;
        if depth {
            size = SOURCE_DEPTH.dimensions();
        } else {
            size = SOURCE.dimensions();
        }
        if gid.x < size.x && gid.y < size.y {
            let first = (gid.y * size.x + gid.x) * msaa;
            for s in 0u32..msaa {
                if depth {
                    SAMPLES[first + s] = SOURCE_DEPTH.load(gid.xy(), s).to_bits();
                } else {
                    SAMPLES[first + s] = SOURCE.load(gid.xy(), s).x;
                }
            }
        }
    }
}
