//! Reading a glTF material: its factors, and each texture reference with the texture's
//! sampler and the reference's `KHR_texture_transform`.

use std::path::Path;

use glam::{Vec2, Vec3, Vec4};
use gltf::json::extensions::texture::TextureTransform as TransformJson;
use gltf::texture::{MagFilter, MinFilter, WrappingMode};

use super::{
    AlphaMode, Filter, Material, SceneError, TextureRef, TextureSampler, UvTransform, Wrap,
};

const TEXTURE_TRANSFORM: &str = "KHR_texture_transform";

/// The material `m`. A malformed `KHR_texture_transform` on the normal or occlusion texture
/// (which gltf 1.4.1 leaves as raw JSON) is an error naming the material.
pub(super) fn material(m: &gltf::Material<'_>, path: &Path) -> Result<Material, SceneError> {
    let pbr = m.pbr_metallic_roughness();
    let normal = m.normal_texture();
    let occlusion = m.occlusion_texture();
    let raw_ref = |texture: gltf::Texture<'_>, tex_coord: u32, ext: Option<&gltf::json::Value>| {
        let transform = ext
            .map(|v| {
                gltf::json::deserialize::from_value::<TransformJson>(v.clone()).map_err(|e| {
                    SceneError::Inconsistent(format!(
                        "{}: material {} has a malformed {TEXTURE_TRANSFORM}: {e}",
                        path.display(),
                        m.index()
                            .map_or_else(|| "default".to_owned(), |i| i.to_string()),
                    ))
                })
            })
            .transpose()?;
        Ok::<_, SceneError>(texture_ref(
            &texture,
            tex_coord,
            transform.as_ref().map(|t| Transform {
                offset: t.offset.0,
                rotation: t.rotation.0,
                scale: t.scale.0,
                tex_coord: t.tex_coord,
            }),
        ))
    };
    Ok(Material {
        name: m.name().unwrap_or("").to_owned(),
        base_color: Vec4::from(pbr.base_color_factor()),
        base_color_texture: pbr.base_color_texture().map(|t| info_ref(&t)),
        metallic: pbr.metallic_factor(),
        roughness: pbr.roughness_factor(),
        metallic_roughness_texture: pbr.metallic_roughness_texture().map(|t| info_ref(&t)),
        normal_scale: normal.as_ref().map_or(1.0, |n| n.scale()),
        normal_texture: normal
            .map(|t| {
                raw_ref(
                    t.texture(),
                    t.tex_coord(),
                    t.extension_value(TEXTURE_TRANSFORM),
                )
            })
            .transpose()?,
        occlusion_strength: occlusion.as_ref().map_or(1.0, |o| o.strength()),
        occlusion_texture: occlusion
            .map(|t| {
                raw_ref(
                    t.texture(),
                    t.tex_coord(),
                    t.extension_value(TEXTURE_TRANSFORM),
                )
            })
            .transpose()?,
        emissive: Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0),
        emissive_texture: m.emissive_texture().map(|t| info_ref(&t)),
        alpha_mode: match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask {
                cutoff: m.alpha_cutoff().unwrap_or(0.5),
            },
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        },
        double_sided: m.double_sided(),
        custom: None,
    })
}

/// A `KHR_texture_transform` as read from either form the gltf crate offers.
struct Transform {
    offset: [f32; 2],
    rotation: f32,
    scale: [f32; 2],
    tex_coord: Option<u32>,
}

/// A plain `textureInfo` (base colour, metallic-roughness, emissive), whose transform gltf
/// parses.
fn info_ref(info: &gltf::texture::Info<'_>) -> TextureRef {
    let transform = info.texture_transform().map(|t| Transform {
        offset: t.offset(),
        rotation: t.rotation(),
        scale: t.scale(),
        tex_coord: t.tex_coord(),
    });
    texture_ref(&info.texture(), info.tex_coord(), transform)
}

/// The reference to `texture` through set `tex_coord`, unless the transform names its own set.
fn texture_ref(
    texture: &gltf::Texture<'_>,
    tex_coord: u32,
    transform: Option<Transform>,
) -> TextureRef {
    let (tex_coord, transform) = match transform {
        Some(t) => (
            t.tex_coord.unwrap_or(tex_coord),
            UvTransform {
                offset: Vec2::from(t.offset),
                rotation: t.rotation,
                scale: Vec2::from(t.scale),
            },
        ),
        None => (tex_coord, UvTransform::IDENTITY),
    };
    TextureRef {
        image: texture.source().index(),
        tex_coord,
        sampler: sampler(&texture.sampler()),
        transform,
    }
}

/// A glTF sampler; filters the file leaves undefined take [`TextureSampler::default`]'s.
pub(super) fn sampler(s: &gltf::texture::Sampler<'_>) -> TextureSampler {
    let wrap = |w| match w {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        WrappingMode::ClampToEdge => Wrap::ClampToEdge,
    };
    let default = TextureSampler::default();
    let (min_filter, mipmap_filter) = match s.min_filter() {
        None => (default.min_filter, default.mipmap_filter),
        Some(MinFilter::Nearest) => (Filter::Nearest, None),
        Some(MinFilter::Linear) => (Filter::Linear, None),
        Some(MinFilter::NearestMipmapNearest) => (Filter::Nearest, Some(Filter::Nearest)),
        Some(MinFilter::LinearMipmapNearest) => (Filter::Linear, Some(Filter::Nearest)),
        Some(MinFilter::NearestMipmapLinear) => (Filter::Nearest, Some(Filter::Linear)),
        Some(MinFilter::LinearMipmapLinear) => (Filter::Linear, Some(Filter::Linear)),
    };
    TextureSampler {
        wrap_u: wrap(s.wrap_s()),
        wrap_v: wrap(s.wrap_t()),
        mag_filter: match s.mag_filter() {
            None => default.mag_filter,
            Some(MagFilter::Nearest) => Filter::Nearest,
            Some(MagFilter::Linear) => Filter::Linear,
        },
        min_filter,
        mipmap_filter,
    }
}
