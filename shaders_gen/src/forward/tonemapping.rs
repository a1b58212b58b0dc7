//! Tonemapping: HDR linear colour to an 8-bit target, as a full-screen fragment pass
//! ([`tonemap`]) or a compute kernel that writes a storage image ([`tonemap_compute`]).

/// What both tonemap programs share: their parameters and the tone curves.
///
/// `tone_mapped(hdr, exposure, curve)` clamps the colour at 0, scales it by `exposure` and maps
/// it through `curve` 0: ACES filmic, Narkowicz's fit `x(2.51x + 0.03) / (x(2.43x + 0.59) +
/// 0.14)` clamped to [0, 1]; or `curve` 1: Khronos PBR Neutral.
#[shader_dsl::library]
pub mod tone_curves {
    pub struct TonemapParams {
        /// Linear scale applied before the curve.
        pub exposure: f32,
        /// Source texels per target pixel: 1 for the frame; a debug view of a texture of
        /// another size (the particle lighting atlas) shows it scaled from the top-left
        /// corner, black beyond its edges.
        pub source_scale: f32,
    }

    /// ACES filmic, Narkowicz's fitted curve, clamped to [0, 1].
    pub fn aces_fitted(x: Vec3) -> Vec3 {
        let num = x * (x * 2.51 + 0.03);
        let den = x * (x * 2.43 + 0.59) + 0.14;
        (num / den).clamp(Vec3::ZERO, Vec3::ONE)
    }

    /// Khronos PBR Neutral.
    pub fn pbr_neutral(c: Vec3) -> Vec3 {
        let start = 0.8 - 0.04;
        let desaturation = 0.15;
        let x = c.x.min(c.y.min(c.z));
        let offset = select(x < 0.08, x - 6.25 * x * x, 0.04);
        let col = c - offset;
        let peak = col.x.max(col.y.max(col.z));
        let mut out = col;
        if peak >= start {
            let d = 1.0 - start;
            let new_peak = 1.0 - d * d / (peak + d - start);
            let scaled = col * (new_peak / peak);
            let g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
            out = scaled.lerp(Vec3::splat(new_peak), g);
        }
        out
    }

    /// `hdr` (negative channels clamped to 0) scaled by `exposure` and mapped by `curve`.
    pub fn tone_mapped(hdr: Vec3, exposure: f32, curve: u32) -> Vec3 {
        let c = hdr.max(Vec3::ZERO) * exposure;
        let mut mapped = c;
        if curve == 0u32 {
            mapped = aces_fitted(c);
        } else {
            mapped = pbr_neutral(c);
        }
        mapped
    }
}

/// Full-screen pass: loads the resolved HDR texel of each pixel (same size as the target, or
/// scaled by `source_scale`), tonemaps it (`tone_curves`), and writes linear colour: an
/// `Rgba8UnormSrgb` target encodes sRGB itself. Alpha is written as 1.
#[shader_dsl::shader(
    axes(curve: u32 = [0, 1] => "curve"),
    uses(crate::forward::tonemapping::tone_curves),
)]
pub mod tonemap {
    #[uniform(group = 0, binding = 0)]
    static PARAMS: TonemapParams;
    #[texture(group = 0, binding = 1, unfilterable)]
    static HDR: Texture2d<f32>;

    #[vertex]
    pub fn vs_fullscreen(#[builtin(vertex_index)] index: u32) -> Vec4 {
        let uv = Vec2::new(((index << 1u32) & 2u32) as f32, (index & 2u32) as f32);
        Vec4::new(uv.x * 2.0 - 1.0, uv.y * 2.0 - 1.0, 0.0, 1.0)
    }

    #[fragment]
    pub fn fs_tonemap(#[builtin(position)] position: Vec4) -> Vec4 {
        let texel = (position.xy() * PARAMS.source_scale).floor().as_uvec2();
        let size = HDR.dimensions();
        let mut hdr = Vec3::ZERO;
        if texel.x < size.x && texel.y < size.y {
            hdr = HDR.load(texel, 0u32).xyz();
        }
        tone_mapped(hdr, PARAMS.exposure, curve).extend(1.0)
    }
}

/// The tonemap as a compute kernel: each invocation tonemaps one pixel as `tonemap` does (the
/// texel under the pixel's centre) and stores it into `OUT`, an `Rgba8Unorm` storage image.
/// Storage images cannot be sRGB, so with `srgb` the kernel encodes sRGB itself (IEC 61966-2-1:
/// `12.92 c` up to 0.0031308, `1.055 c^(1/2.4) - 0.055` above) and the image is copied into an
/// `Rgba8UnormSrgb` target unchanged; without it the values stay linear. Alpha is 1.
///
/// On GPUs whose fragment rate is far below their compute rate this costs a tenth of the
/// full-screen pass (see BENCHMARKS.md).
#[shader_dsl::shader(
    axes(curve: u32 = [0, 1] => "curve", srgb: bool = [false, true] => "srgb"),
    uses(crate::forward::tonemapping::tone_curves),
)]
pub mod tonemap_compute {
    #[uniform(group = 0, binding = 0)]
    static PARAMS: TonemapParams;
    #[texture(group = 0, binding = 1, unfilterable)]
    static HDR: Texture2d<f32>;
    #[texture(group = 0, binding = 2)]
    static OUT: StorageTexture2d<Rgba8Unorm, Write>;

    /// sRGB's encoding of one linear channel in [0, 1].
    fn srgb_encoded(x: f32) -> f32 {
        select(x <= 0.0031308, x * 12.92, 1.055 * x.powf(1.0 / 2.4) - 0.055)
    }

    #[compute(workgroup_size(8, 8, 1))]
    pub fn cs_tonemap(#[builtin(global_invocation_id)] gid: UVec3) {
        let pixel = gid.xy();
        let out_size = OUT.dimensions();
        if pixel.x < out_size.x && pixel.y < out_size.y {
            let centre = pixel.as_vec2() + Vec2::splat(0.5);
            let texel = (centre * PARAMS.source_scale).floor().as_uvec2();
            let size = HDR.dimensions();
            let mut hdr = Vec3::ZERO;
            if texel.x < size.x && texel.y < size.y {
                hdr = HDR.load(texel, 0u32).xyz();
            }
            let mut mapped = tone_mapped(hdr, PARAMS.exposure, curve);
            if srgb {
                mapped = Vec3::new(
                    srgb_encoded(mapped.x),
                    srgb_encoded(mapped.y),
                    srgb_encoded(mapped.z),
                );
            }
            OUT.store(pixel, mapped.extend(1.0));
        }
    }
}
