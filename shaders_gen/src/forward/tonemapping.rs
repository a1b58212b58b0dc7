//! Tonemapping: HDR linear colour to an sRGB 8-bit target.

/// Full-screen pass: loads the resolved HDR texel of each pixel (same size as the target, or
/// scaled by `source_scale`),
/// multiplies by `exposure` and tonemaps it, writing linear colour for an `Rgba8UnormSrgb`
/// target (the format encodes sRGB).
///
/// `curve` 0: ACES filmic, Narkowicz's fit `x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14)`;
/// `curve` 1: Khronos PBR Neutral. Alpha is written as 1.
#[shader_dsl::shader(axes(curve: u32 = [0, 1] => "curve"))]
pub mod tonemap {
    pub struct TonemapParams {
        /// Linear scale applied before the curve.
        pub exposure: f32,
        /// Source texels per target pixel: 1 for the frame; a debug view of a texture of
        /// another size (the particle lighting atlas) shows it scaled from the top-left
        /// corner, black beyond its edges.
        pub source_scale: f32,
    }

    #[uniform(group = 0, binding = 0)]
    static PARAMS: TonemapParams;
    #[texture(group = 0, binding = 1, unfilterable)]
    static HDR: Texture2d<f32>;

    #[vertex]
    pub fn vs_fullscreen(#[builtin(vertex_index)] index: u32) -> Vec4 {
        let uv = Vec2::new(((index << 1u32) & 2u32) as f32, (index & 2u32) as f32);
        Vec4::new(uv.x * 2.0 - 1.0, uv.y * 2.0 - 1.0, 0.0, 1.0)
    }

    /// ACES filmic, Narkowicz's fitted curve, clamped to [0, 1].
    fn aces_fitted(x: Vec3) -> Vec3 {
        let num = x * (x * 2.51 + 0.03);
        let den = x * (x * 2.43 + 0.59) + 0.14;
        (num / den).clamp(Vec3::ZERO, Vec3::ONE)
    }

    /// Khronos PBR Neutral.
    fn pbr_neutral(c: Vec3) -> Vec3 {
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

    #[fragment]
    pub fn fs_tonemap(#[builtin(position)] position: Vec4) -> Vec4 {
        let texel = (position.xy() * PARAMS.source_scale).floor().as_uvec2();
        let size = HDR.dimensions();
        let mut hdr = Vec3::ZERO;
        if texel.x < size.x && texel.y < size.y {
            hdr = HDR.load(texel, 0u32).xyz();
        }
        let c = hdr.max(Vec3::ZERO) * PARAMS.exposure;
        let mut mapped = c;
        if curve == 0 {
            mapped = aces_fitted(c);
        } else {
            mapped = pbr_neutral(c);
        }
        mapped.extend(1.0)
    }
}
