//! How a prepared material reads its textures: each texture reference's UV set and
//! `KHR_texture_transform` as the shaders' `UvMap`, and the wgpu sampler a glTF sampler would be
//! (the material atlas does its wrap and filters in the shader; tests compare the two).

use shaders_gen::shared::material_uv::UvMap;

use crate::scene::TextureRef;
#[cfg(any(test, feature = "internals"))]
use crate::scene::{Filter, TextureSampler, Wrap};

/// The wgpu sampler of a glTF sampler. Without a mipmap filter only level 0 is read
/// (`lod_max_clamp` 0), as glTF's `NEAREST` and `LINEAR` minification filters mean.
#[cfg(any(test, feature = "internals"))]
pub fn sampler_descriptor(s: TextureSampler) -> wgpu::SamplerDescriptor<'static> {
    let wrap = |w: Wrap| match w {
        Wrap::Repeat => wgpu::AddressMode::Repeat,
        Wrap::MirroredRepeat => wgpu::AddressMode::MirrorRepeat,
        Wrap::ClampToEdge => wgpu::AddressMode::ClampToEdge,
    };
    let filter = |f: Filter| match f {
        Filter::Nearest => wgpu::FilterMode::Nearest,
        Filter::Linear => wgpu::FilterMode::Linear,
    };
    let mipmap_filter = match s.mipmap_filter {
        Some(Filter::Linear) => wgpu::MipmapFilterMode::Linear,
        Some(Filter::Nearest) | None => wgpu::MipmapFilterMode::Nearest,
    };
    wgpu::SamplerDescriptor {
        label: Some("material sampler"),
        address_mode_u: wrap(s.wrap_u),
        address_mode_v: wrap(s.wrap_v),
        mag_filter: filter(s.mag_filter),
        min_filter: filter(s.min_filter),
        mipmap_filter,
        lod_max_clamp: if s.mipmap_filter.is_some() { 32.0 } else { 0.0 },
        ..Default::default()
    }
}

/// The shaders' `UvMap` of `texture`: its UV set and the first two rows of its transform
/// (identity over `TEXCOORD_0` where there is no texture).
pub fn uv_map(texture: Option<TextureRef>) -> UvMap {
    let (set, transform) = texture.map_or((0, glam::Mat3::IDENTITY), |t| {
        (t.tex_coord, t.transform.matrix())
    });
    let rows = transform.transpose();
    UvMap::new(rows.x_axis, set, rows.y_axis)
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};

    use super::*;
    use crate::scene::UvTransform;

    #[test]
    fn sampler_modes_follow_the_file() {
        let s = TextureSampler {
            wrap_u: Wrap::MirroredRepeat,
            wrap_v: Wrap::ClampToEdge,
            mag_filter: Filter::Nearest,
            min_filter: Filter::Linear,
            mipmap_filter: None,
        };
        let d = sampler_descriptor(s);
        assert_eq!(d.address_mode_u, wgpu::AddressMode::MirrorRepeat);
        assert_eq!(d.address_mode_v, wgpu::AddressMode::ClampToEdge);
        assert_eq!(d.mag_filter, wgpu::FilterMode::Nearest);
        assert_eq!(d.min_filter, wgpu::FilterMode::Linear);
        assert_eq!(d.lod_max_clamp, 0.0, "no mipmap filter: level 0 only");
        let d = sampler_descriptor(TextureSampler {
            mipmap_filter: Some(Filter::Linear),
            ..s
        });
        assert_eq!(d.mipmap_filter, wgpu::MipmapFilterMode::Linear);
        assert!(d.lod_max_clamp > 10.0);
    }

    #[test]
    fn uv_map_rows_apply_the_transform() {
        let t = TextureRef {
            tex_coord: 1,
            transform: UvTransform {
                offset: Vec2::new(0.5, -0.25),
                rotation: std::f32::consts::FRAC_PI_2,
                scale: Vec2::new(2.0, 3.0),
            },
            ..TextureRef::new(0)
        };
        let m = uv_map(Some(t));
        assert_eq!(m.uv_set, 1);
        let uv = Vec3::new(0.25, 0.5, 1.0);
        // Scale (0.5, 1.5), rotate a quarter turn as KHR_texture_transform's matrix does
        // ((x, y) → (x cos + y sin, −x sin + y cos)): (1.5, −0.5), offset: (2.0, −0.75).
        let mapped = Vec2::new(m.row_u.dot(uv), m.row_v.dot(uv));
        assert!((mapped - Vec2::new(2.0, -0.75)).length() < 1e-5, "{mapped}");
        let identity = uv_map(None);
        assert_eq!(identity.uv_set, 0);
        assert_eq!((identity.row_u, identity.row_v), (Vec3::X, Vec3::Y));
    }
}
