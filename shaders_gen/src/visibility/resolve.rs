//! The compute rasteriser's depths written into a multisampled depth target, for a pass after
//! the visibility raster that reads a depth target.

/// Full-screen pass at sample rate: each invocation reads its sample of `VIS64` (the compute
/// rasteriser's buffer, `vis_compute_raster`, two 32-bit words a sample, the low word first)
/// and writes the depth it holds (`vis64_depth`), 1.0 (sky) where no triangle covered the
/// sample. Every sample is written, so the target is never cleared: on chips with a slow
/// fixed-function fill a multisampled depth clear costs nearly as much as this whole pass
/// (0.60 ms at MSAA 4 on the H200, where the pass with the clear took 1.41 and now 0.81). The IDs
/// stay in the buffer, which the shading kernels read.
#[shader_dsl::shader(uses(crate::visibility::samples64::vis64_sample))]
pub mod vis_resolve {
    /// The frame's size and sample count, for the sample's index in `VIS64`.
    pub struct ResolveParams {
        pub width: u32,
        pub msaa: u32,
        pub pad: UVec2,
    }

    /// What a sample gets.
    pub struct ResolveOut {
        #[builtin(frag_depth)]
        pub depth: f32,
    }

    #[uniform(group = 0, binding = 0)]
    static PARAMS: ResolveParams;
    /// The compute rasteriser's samples, as `(low, high)` word pairs.
    #[storage(group = 0, binding = 1)]
    static VIS64: [UVec2];

    #[vertex]
    pub fn vs_fullscreen(#[builtin(vertex_index)] index: u32) -> Vec4 {
        let uv = Vec2::new(((index << 1u32) & 2u32) as f32, (index & 2u32) as f32);
        Vec4::new(uv.x * 2.0 - 1.0, uv.y * 2.0 - 1.0, 0.0, 1.0)
    }

    #[fragment]
    pub fn fs_resolve(
        #[builtin(position)] position: Vec4,
        #[builtin(sample_index)] sample: u32,
    ) -> ResolveOut {
        let p = position.xy().floor().as_uvec2();
        let depth = vis64_depth(VIS64[(p.y * PARAMS.width + p.x) * PARAMS.msaa + sample]);
        ResolveOut { depth }
    }
}
