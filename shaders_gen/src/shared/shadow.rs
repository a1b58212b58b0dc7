//! Shadow lookup, shared by every pass that lights a point: the forward pass today, and the
//! compute-shading and particle-lighting passes later.

/// The shadow atlas as shading reads it, and `shadow_visibility`, the one PCF path of every
/// light type.
///
/// A shadowed light's record carries `shadow`: the index of its first [`ShadowView`] in
/// `SHADOW_VIEWS` (or [`NO_SHADOW`]). The first view's `faces` says what follows:
///
/// * 1: a spot light, one perspective view;
/// * 6: a point light, six perspective cube faces (+X, −X, +Y, −Y, +Z, −Z); the face is the major
///   axis of the point seen from the light ([`cube_face`]). Each face is rendered with a guard
///   band of texels beyond its 90° edge, so the filter never leaves its face's region and
///   face edges have no seams;
/// * 4: the directional light's cascades, in order of distance; a point takes the first cascade
///   whose `split_far` lies beyond its view depth, and in the last [`CASCADE_BLEND`] of a
///   cascade it takes the next one with a probability rising linearly (a dithered transition).
///
/// Every view is reversed Z (near 1, far 0), compared with `GreaterEqual`: a point is lit where
/// its depth is nearer the light than (or as near as) the stored caster. The lookup offsets the
/// point along its geometric normal by `normal_offset` texels of the view at that distance
/// (normal-offset bias; the caster pass adds slope-scaled depth bias), and filters with a 3×3
/// grid of bilinear comparisons one texel apart (a 4×4-texel tent), each clamped half a texel
/// inside the region so no neighbour's depth is read.
#[shader_dsl::library]
pub mod shadow_atlas {
    /// One shadow map in the atlas.
    pub struct ShadowView {
        /// World → clip, reversed Z; x, y in [−1, 1] cover the region.
        pub clip_from_world: Mat4,
        /// The region in atlas UV: `xy` its corner, `zw` its size.
        pub rect: Vec4,
        /// World size of a texel: at unit distance from a perspective view's eye (times the
        /// distance), or absolute for an orthographic view.
        pub texel_world: f32,
        /// Non-zero for an orthographic (directional) view.
        pub orthographic: u32,
        /// Cascades: the camera view depth where this cascade ends; 0 otherwise.
        pub split_far: f32,
        /// Views of this light from this one on: 1 spot, 6 cube faces, 4 cascades (first view
        /// only; later views repeat it).
        pub faces: u32,
    }

    /// `GpuLight::shadow` of a light without a shadow this frame.
    pub const NO_SHADOW: u32 = 0xFFFF_FFFF;
    /// Fraction of a cascade's depth range over which it dithers into the next one.
    pub const CASCADE_BLEND: f32 = 0.15;
    /// Normal offset, in texels of the view at the shaded point.
    pub const NORMAL_OFFSET: f32 = 1.5;

    #[storage(group = 0, binding = 6)]
    static SHADOW_VIEWS: [ShadowView];
    #[texture(group = 0, binding = 7)]
    static SHADOW_ATLAS: TextureDepth2d;
    #[sampler(group = 0, binding = 8)]
    static SHADOW_SAMPLER: SamplerComparison;

    /// The cube face of direction `d` (from the light): its major axis, `0`/`1` for ±X, `2`/`3`
    /// for ±Y, `4`/`5` for ±Z; ties go to X before Y before Z, and zero to the positive face.
    pub fn cube_face(d: Vec3) -> u32 {
        let a = d.abs();
        let mut face = 4u32 + select(d.z >= 0.0, 0u32, 1u32);
        if a.x >= a.y && a.x >= a.z {
            face = select(d.x >= 0.0, 0u32, 1u32);
        } else if a.y >= a.z {
            face = 2u32 + select(d.y >= 0.0, 0u32, 1u32);
        }
        face
    }

    /// Interleaved gradient noise of a pixel, in [0, 1): the cascade dither.
    pub fn dither_noise(pixel: Vec2) -> f32 {
        (52.982_918 * (0.067_110_56 * pixel.x + 0.005_837_15 * pixel.y).fract()).fract()
    }

    /// The cascade of view depth `view_depth` from `first` (4 views), dithered by `dither`;
    /// 4 when the point lies beyond the last cascade.
    fn cascade_of(first: u32, view_depth: f32, dither: f32) -> u32 {
        let mut c = 0u32;
        let mut start = 0.0;
        for i in 0u32..4u32 {
            if c == i && view_depth > SHADOW_VIEWS[first + i].split_far {
                c = i + 1u32;
                start = SHADOW_VIEWS[first + i].split_far;
            }
        }
        if c < 3u32 {
            let end = SHADOW_VIEWS[first + c].split_far;
            let blend_start = end - CASCADE_BLEND * (end - start);
            let t = (view_depth - blend_start) / (end - blend_start);
            if t > 0.0 && dither < t {
                c += 1u32;
            }
        }
        c
    }

    /// Filtered visibility of world point `p` in `view`: 3×3 bilinear comparisons.
    fn filtered(view: ShadowView, p: Vec3) -> f32 {
        let clip = view.clip_from_world * p.extend(1.0);
        let ndc = clip.xyz() / clip.w;
        let mut lit = 1.0;
        if ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0 && ndc.z >= 0.0 && ndc.z <= 1.0 {
            let texel = Vec2::ONE / SHADOW_ATLAS.dimensions().as_vec2();
            let uv = Vec2::new(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
            let centre = view.rect.xy() + uv * view.rect.zw();
            let lo = view.rect.xy() + texel * 0.5;
            let hi = view.rect.xy() + view.rect.zw() - texel * 0.5;
            let mut sum = 0.0;
            for j in 0u32..3u32 {
                for i in 0u32..3u32 {
                    let offset = Vec2::new(i as f32 - 1.0, j as f32 - 1.0) * texel;
                    let at = (centre + offset).clamp(lo, hi);
                    sum += SHADOW_ATLAS.sample_compare_level(SHADOW_SAMPLER, at, ndc.z);
                }
            }
            lit = sum / 9.0;
        }
        lit
    }

    /// How much of a light reaches world point `p` (1 lit, 0 shadowed), for the light whose
    /// record says `shadow` and sits at `light_position` (unused for directional lights).
    /// `geometric_normal` is the surface's unit normal (not normal-mapped), `view_depth` the
    /// camera view depth of `p` and `dither` a per-pixel value in [0, 1) ([`dither_noise`]).
    pub fn shadow_visibility(
        shadow: u32,
        light_position: Vec3,
        p: Vec3,
        geometric_normal: Vec3,
        view_depth: f32,
        dither: f32,
    ) -> f32 {
        let mut lit = 1.0;
        if shadow != NO_SHADOW {
            let faces = SHADOW_VIEWS[shadow].faces;
            let mut index = shadow;
            let mut inside = true;
            if faces == 4u32 {
                let c = cascade_of(shadow, view_depth, dither);
                inside = c < 4u32;
                index = shadow + c.min(3u32);
            }
            // The offset point, in texels of the chosen view (all six cube faces share one
            // texel size). A cube face is picked from the offset point, so the lookup never
            // leaves that face's region.
            let mut texel = SHADOW_VIEWS[index].texel_world;
            if SHADOW_VIEWS[index].orthographic == 0u32 {
                texel = texel * (p - light_position).length();
            }
            let q = p + geometric_normal * (texel * NORMAL_OFFSET);
            if faces == 6u32 {
                index = shadow + cube_face(q - light_position);
            }
            if inside {
                lit = filtered(SHADOW_VIEWS[index], q);
            }
        }
        lit
    }
}
