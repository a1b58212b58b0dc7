//! What the deferred paths draw over their shaded image with MSAA (blended surfaces, then
//! particles) is drawn into a transparent multisampled overlay; this kernel resolves that
//! overlay and lays it over the shaded image.

/// Each invocation resolves one pixel of `OVERLAY` (the mean of its samples: premultiplied
/// colour, and the coverage `1 - Π(1 - aᵢ)` of the layers drawn into it) and lays it over the
/// same pixel of `SHADED`: `overlay + (1 - overlay.a) · shaded`, into `HDR_OUT`. Resolving here
/// rather than in the render passes that draw the overlay saves writing a resolved image each.
///
/// This equals drawing every layer over the shaded pixel in each sample and resolving: each
/// layer maps a colour `d` to `c + (1 - a) d`, such maps compose into one of the same form (the
/// overlay's sample), and the resolve's mean commutes with them where the pixel below is one
/// colour, which the deferred image is.
#[shader_dsl::shader(axes(msaa: u32 = [2, 4, 8]))]
pub mod hdr_overlay {
    #[texture(group = 0, binding = 0, unfilterable)]
    static SHADED: Texture2d<f32>;
    #[texture(group = 0, binding = 1, unfilterable)]
    static OVERLAY: TextureMultisampled2d<f32>;
    #[texture(group = 0, binding = 2)]
    static HDR_OUT: StorageTexture2d<Rgba16Float, Write>;

    #[compute(workgroup_size(8, 8, 1))]
    pub fn lay_over(#[builtin(global_invocation_id)] gid: UVec3) {
        let pixel = gid.xy();
        let size = HDR_OUT.dimensions();
        if pixel.x < size.x && pixel.y < size.y {
            let below = SHADED.load(pixel, 0u32);
            let mut sum = Vec4::new(0.0, 0.0, 0.0, 0.0);
            for s in 0u32..msaa {
                sum = sum + OVERLAY.load(pixel, s);
            }
            let over = sum / (msaa as f32);
            HDR_OUT.store(pixel, over + below * (1.0 - over.w));
        }
    }
}

/// The overlay is kept between frames and never cleared (a multisampled clear ran at a fiftieth
/// of the memory's speed on the H200). Instead, once `hdr_overlay` has laid it over the image,
/// every pass that drew into it draws the same geometry again with its own vertex stage and this
/// fragment stage, without blending or a depth test: the samples it covered (and perhaps more)
/// go back to transparent, so the next frame's first layer blends over transparent samples, as
/// over a cleared target.
#[shader_dsl::shader]
pub mod overlay_erase {
    /// Transparent black, written over whatever the sample held.
    #[fragment]
    pub fn fs_erase() -> Vec4 {
        Vec4::ZERO
    }
}
