//! The visibility raster pass.

/// Visibility raster: every opaque and alpha-masked draw of the scene writes depth and, per
/// sample, the ID of its triangle (`vis_geometry`'s numbering) to an `R32Uint` target. It
/// replaces pre-Z and the G-buffer of the deferred paths: what a sample sees is found again in
/// compute from the ID.
///
/// The vertices are pulled from storage rather than vertex buffers, so a triangle knows its
/// number without `primitive_index` (which WebGPU lacks): the pass draws the scene's indexed
/// draws, with their indirect arguments unchanged, over a *sequence* index buffer whose index
/// `i` is `i`, so `vertex_index − base_vertex` is the position in the scene's index buffer. The
/// ID leaves the provoking (first) vertex flat.
///
/// The clip position is `view`'s `clip_position`, `#[invariant]`, as every geometry pass's.
/// Alpha-masked materials (`alpha_mask`) discard what the masked pre-Z discards
/// (`material_table`'s `masked_out`), so the IDs and the depth agree with the other paths.
///
/// With `vis64` (masked draws only), under the compute rasteriser: the masked draws add their
/// samples to its buffer (`vis_compute_raster`'s `VIS64`, the same packing and `fetch_max`)
/// instead of writing an ID target, at the frame's sample count (`msaa`, 0 without `vis64`).
/// The fragment stage runs once a pixel, as the other paths' masked draws: the alpha test at
/// the pixel centre, then each covered sample (the `sample_mask` input) merges its own depth,
/// taken on the triangle's plane through the screen derivatives of the fragment's depth as the
/// hardware interpolates it at the sample (`sample_pattern`'s positions). A fragment stage run
/// per sample (reading `sample_index`) cost four to eight invocations a pixel on a chip whose
/// fragment rate is far below its compute rate (BENCHMARKS.md).
#[shader_dsl::shader(
    axes(
        alpha_mask: bool = [false, true] => "mask",
        vis64: bool = [false, true] => "vis64",
        msaa: u32 = [0, 1, 2, 4, 8] => "msaa",
    ),
    exclude(vis64 && !alpha_mask),
    exclude(vis64 && msaa == 0),
    exclude(!vis64 && msaa > 0),
    uses(
        crate::shared::sample_pattern,
        crate::shared::view,
        crate::shared::material_uv,
        crate::shared::material_table,
        crate::visibility::geometry::vis_geometry,
    ),
)]
pub mod vis_raster {
    pub struct VisVsOut {
        #[builtin(position)]
        #[invariant]
        pub clip: Vec4,
        /// The triangle's ID.
        #[location(0)]
        #[interpolate(flat)]
        pub id: u32,
        #[location(1)]
        pub uv0: Vec2,
        #[location(2)]
        pub uv1: Vec2,
        #[location(3)]
        pub color_alpha: f32,
        #[location(4)]
        #[interpolate(flat)]
        pub material: u32,
    }

    #[uniform(group = 0, binding = 0)]
    static CAMERA: Camera;
    /// The compute rasteriser's samples and the frame's width (`vis64`).
    #[storage(group = 0, binding = 1, read_write)]
    #[when(vis64)]
    static VIS64: [Atomic<u64>];
    #[uniform(group = 0, binding = 2)]
    #[when(vis64)]
    static SAMPLES: SampleLayout;

    /// Where a sample is in `VIS64`: `(y × width + x) × msaa + s` (`msaa` the variant's).
    pub struct SampleLayout {
        pub width: u32,
        pub pad: UVec3,
    }

    #[vertex]
    pub fn vs_vis(
        #[builtin(vertex_index)] index: u32,
        #[builtin(instance_index)] draw: u32,
    ) -> VisVsOut {
        let pulled = pulled_vertex(index, draw);
        let v = pulled.vertex;
        let mut out = VisVsOut {
            clip: clip_position(
                CAMERA.view_projection,
                DRAWS[draw].world_from_mesh,
                vertex_position(v),
            ),
            id: pulled.triangle,
            uv0: Vec2::ZERO,
            uv1: Vec2::ZERO,
            color_alpha: 1.0,
            material: DRAWS[draw].material,
        };
        if alpha_mask {
            out.uv0 = UV0[v];
            out.uv1 = UV1[v];
            out.color_alpha = COLORS[v].w;
        }
        out
    }

    /// The sample's triangle; masked materials' texels below the cutoff leave nothing.
    #[fragment]
    pub fn fs_vis(input: VisVsOut) -> VisOut {
        if alpha_mask
            && masked_out(
                input.material,
                uv_derivatives(input.uv0, input.uv1),
                input.color_alpha,
            )
        {
            discard();
        }
        VisOut { id: input.id }
    }

    /// `vis64`: at each sample of `coverage`, the fragment's depth there and its triangle into
    /// `VIS64` where nearer than what is there; masked materials' texels below the cutoff leave
    /// nothing. The renderer draws it with no depth test over a scratch depth target it neither
    /// loads nor stores: the 64-bit atomics are the depth test.
    #[fragment]
    #[when(vis64)]
    pub fn fs_vis64(input: VisVsOut, #[builtin(sample_mask)] coverage: u32) {
        // Derivatives first, where every invocation of the quad takes them.
        let slope = Vec2::new(dpdx(input.clip.z), dpdy(input.clip.z));
        let cut = masked_out(
            input.material,
            uv_derivatives(input.uv0, input.uv1),
            input.color_alpha,
        );
        if !cut {
            // The position is the pixel centre's window position and depth.
            let p = input.clip.xy().floor().as_uvec2();
            let first = (p.y * SAMPLES.width + p.x) * msaa;
            for s in 0u32..msaa {
                let z = input.clip.z + slope.dot(sample_offset(s) - Vec2::splat(0.5));
                if ((coverage >> s) & 1u32) != 0u32 && z >= 0.0 && z < 1.0 {
                    // `& 0x7FFF_FFFF`: -0.0 ranks as 0.0, as in the compute rasteriser.
                    let depth = z.to_bits() & 0x7FFF_FFFFu32;
                    let packed = ((!depth as u64) << 32u32) | ((!input.id) as u64);
                    VIS64[first + s].fetch_max(packed);
                }
            }
        }
    }

    pub struct VisOut {
        #[location(0)]
        pub id: u32,
    }
}
