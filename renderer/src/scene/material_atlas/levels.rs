//! What the material atlas stores of one image: the texture it serves (`AtlasKey`), its levels
//! from the first that fits (`stored_levels`), shared by the textures whose borders agree
//! (`LevelsKey`), each written inside its one-texel wrap border (`write_bordered`), and the
//! shader's wrap and filter bits of a sampler.

use shaders_gen::shared::material_atlas::{
    FILTER_MAG_NEAREST, FILTER_MIN_NEAREST, FILTER_MIP_SHIFT, MIP_LINEAR, MIP_NEAREST, MIP_NONE,
    WRAP_CLAMP, WRAP_MIRROR, WRAP_REPEAT,
};

use crate::scene::mips::{level_count, mip_chain};
use crate::scene::{Filter, Image, TextureSampler, Wrap};

/// One material texture: an image, the sampler that reads it, and whether its texels are sRGB
/// colour (base colour, emissive) or data (normals, metallic-roughness, occlusion).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct AtlasKey {
    /// Index into the images the atlas is given (the scene's [`crate::scene::Scene::images`]).
    pub image: usize,
    /// Its wrap modes decide the stored border; its filters go to the shader's record.
    pub sampler: TextureSampler,
    /// `true`: sRGB colour, mipmapped in linear light; `false`: linear data.
    pub colour: bool,
}

/// The levels of one image with one kind of border.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(super) struct LevelsKey {
    pub(super) image: usize,
    pub(super) colour: bool,
    pub(super) repeat_u: bool,
    pub(super) repeat_v: bool,
}

/// Where one stored level went.
#[derive(Debug, Clone, Copy)]
pub(super) struct Placed {
    pub(super) layer: u32,
    pub(super) x: u32,
    pub(super) y: u32,
    pub(super) width: u32,
    pub(super) height: u32,
    /// Its rectangle in its page's allocator, to give back when nothing samples it.
    pub(super) allocation: etagere::AllocId,
}

/// One stored level: width, height and RGBA8 texels.
pub(super) type Level = (u32, u32, Vec<u8>);

/// The levels `key` samples: its image, as colour or data, with its borders.
pub(super) fn levels_key(key: &AtlasKey) -> LevelsKey {
    LevelsKey {
        image: key.image,
        colour: key.colour,
        repeat_u: key.sampler.wrap_u == Wrap::Repeat,
        repeat_v: key.sampler.wrap_v == Wrap::Repeat,
    }
}

/// The levels of `image` stored in the atlas, `(width, height, RGBA8 texels)`, from the first
/// whose bordered rectangle fits `max_side` (a texture larger than the device's largest is
/// sampled as if its first fitting level were its level 0).
pub(super) fn stored_levels(image: &Image, colour: bool, max_side: u32) -> Vec<Level> {
    let chain = mip_chain(image, colour);
    let mut levels = Vec::new();
    let mut offset = 0;
    for level in 0..level_count(image.width, image.height) {
        let (w, h) = (
            (image.width >> level).max(1),
            (image.height >> level).max(1),
        );
        let bytes = (w * h * 4) as usize;
        if w.max(h) + 2 <= max_side {
            levels.push((w, h, chain[offset..offset + bytes].to_vec()));
        }
        offset += bytes;
    }
    levels
}

/// Writes one level with its border: beside each edge, the texel the wrap puts there (the
/// opposite edge where the axis repeats, the edge itself otherwise).
pub(super) fn write_bordered(
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    at: Placed,
    texels: &[u8],
    repeat_u: bool,
    repeat_v: bool,
) {
    let (w, h) = (at.width as i64, at.height as i64);
    let source = |i: i64, n: i64, repeat: bool| -> i64 {
        if i < 0 {
            if repeat { n - 1 } else { 0 }
        } else if i >= n {
            if repeat { 0 } else { n - 1 }
        } else {
            i
        }
    };
    let mut bordered = Vec::with_capacity(((w + 2) * (h + 2) * 4) as usize);
    for y in -1..=h {
        let sy = source(y, h, repeat_v);
        for x in -1..=w {
            let sx = source(x, w, repeat_u);
            let i = ((sy * w + sx) * 4) as usize;
            bordered.extend_from_slice(&texels[i..i + 4]);
        }
    }
    queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d {
                x: at.x,
                y: at.y,
                z: at.layer,
            },
            aspect: wgpu::TextureAspect::All,
        },
        &bordered,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some((at.width + 2) * 4),
            rows_per_image: None,
        },
        wgpu::Extent3d {
            width: at.width + 2,
            height: at.height + 2,
            depth_or_array_layers: 1,
        },
    );
}

pub(super) fn wrap_bits(s: TextureSampler) -> u32 {
    let bits = |w: Wrap| match w {
        Wrap::Repeat => WRAP_REPEAT,
        Wrap::MirroredRepeat => WRAP_MIRROR,
        Wrap::ClampToEdge => WRAP_CLAMP,
    };
    bits(s.wrap_u) | (bits(s.wrap_v) << 2)
}

pub(super) fn filter_bits(s: TextureSampler) -> u32 {
    let mut bits = 0;
    if s.mag_filter == Filter::Nearest {
        bits |= FILTER_MAG_NEAREST;
    }
    if s.min_filter == Filter::Nearest {
        bits |= FILTER_MIN_NEAREST;
    }
    let mip = match s.mipmap_filter {
        None => MIP_NONE,
        Some(Filter::Nearest) => MIP_NEAREST,
        Some(Filter::Linear) => MIP_LINEAR,
    };
    bits | (mip << FILTER_MIP_SHIFT)
}
