//! The material atlas, host side of `shaders_gen::shared::material_atlas`: every mip level of
//! every material texture packed with `etagere` into the layers of one 2D array texture, each
//! level at its own rectangle inside a one-texel border that holds what the texture's wrap mode
//! puts beside the edge. A shader reaches a texture by its index ([`MaterialAtlas::index`]), so
//! one bind group serves every material, on WebGPU as on Vulkan.
//!
//! Levels are shared by every texture of one image whose borders agree (the same image, as
//! colour or data, repeating or not along each axis; mirrored repeat and clamp borders are the
//! same), so an image sampled by two samplers is stored once unless their borders differ.

use std::collections::HashMap;

use etagere::{AtlasAllocator, size2};
use shaders_gen::shared::material_atlas::{
    AtlasLevel, AtlasTexture, FILTER_MAG_NEAREST, FILTER_MIN_NEAREST, FILTER_MIP_SHIFT, MIP_LINEAR,
    MIP_NEAREST, MIP_NONE, WRAP_CLAMP, WRAP_MIRROR, WRAP_REPEAT,
};
use wgpu::util::DeviceExt as _;

use super::mips::{level_count, mip_chain};
use super::{Filter, Image, TextureSampler, Wrap};

/// One material texture: an image, the sampler that reads it, and whether its texels are sRGB
/// colour (base colour, emissive) or data (normals, metallic-roughness, occlusion).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct AtlasKey {
    pub image: usize,
    pub sampler: TextureSampler,
    pub colour: bool,
}

/// What the atlas cannot hold.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum AtlasError {
    #[error("material texture names image {image}, but the scene has {images} images")]
    UnknownImage { image: usize, images: usize },
    #[error(
        "the material textures need {layers} atlas layers of {size}×{size} texels; the device \
         allows {limit} (fewer or smaller images are needed)"
    )]
    TooManyLayers { layers: u32, size: u32, limit: u32 },
}

/// The levels of one image with one kind of border.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
struct LevelsKey {
    image: usize,
    colour: bool,
    repeat_u: bool,
    repeat_v: bool,
}

/// Where one stored level went.
#[derive(Debug, Clone, Copy)]
struct Placed {
    layer: u32,
    x: u32,
    y: u32,
    width: u32,
    height: u32,
}

/// Every material texture of a scene in one array texture, with the records the shader reads.
#[derive(Debug)]
pub struct MaterialAtlas {
    texture: wgpu::Texture,
    colour_view: wgpu::TextureView,
    data_view: wgpu::TextureView,
    sampler: wgpu::Sampler,
    textures: wgpu::Buffer,
    levels: wgpu::Buffer,
    indices: HashMap<AtlasKey, u32>,
    page_size: u32,
}

/// The smallest page side, so small scenes still pack several textures per layer.
const MIN_PAGE: u32 = 256;

impl MaterialAtlas {
    /// Packs `keys` (duplicates are stored once) of `images` into a new atlas. Images whose
    /// level 0 does not fit the device's largest texture start at their first level that does.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        images: &[impl std::borrow::Borrow<Image>],
        keys: &[AtlasKey],
    ) -> Result<Self, AtlasError> {
        let limits = device.limits();
        let max_side = limits.max_texture_dimension_2d;
        let level_sets = distinct_level_sets(images, keys)?;
        // Each set's stored levels: the chain from the first level that fits a page.
        let chains: Vec<Vec<(u32, u32, Vec<u8>)>> = level_sets
            .iter()
            .map(|set| stored_levels(images[set.image].borrow(), set.colour, max_side))
            .collect();
        let widest = chains
            .iter()
            .flat_map(|levels| levels.first())
            .map(|(w, h, _)| (*w).max(*h) + 2)
            .max()
            .unwrap_or(1);
        let page_size = widest.next_power_of_two().clamp(MIN_PAGE, max_side);
        let (pages, placed) = pack(&chains, page_size);
        let layers = pages.max(1);
        if layers > limits.max_texture_array_layers {
            return Err(AtlasError::TooManyLayers {
                layers,
                size: page_size,
                limit: limits.max_texture_array_layers,
            });
        }
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("material atlas"),
            size: wgpu::Extent3d {
                width: page_size,
                height: page_size,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[wgpu::TextureFormat::Rgba8UnormSrgb],
        });
        let (mut level_records, first_level) =
            write_levels(queue, &texture, &level_sets, &chains, &placed, page_size);
        let (indices, mut texture_records) =
            texture_records(keys, &level_sets, &chains, &first_level);
        // Storage buffers are never empty.
        if level_records.is_empty() {
            level_records.push(bytemuck::Zeroable::zeroed());
        }
        if texture_records.is_empty() {
            texture_records.push(bytemuck::Zeroable::zeroed());
        }
        let storage = |label, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let view = |format| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                label: Some("material atlas"),
                format: Some(format),
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            })
        };
        Ok(Self {
            colour_view: view(wgpu::TextureFormat::Rgba8UnormSrgb),
            data_view: view(wgpu::TextureFormat::Rgba8Unorm),
            sampler: atlas_sampler(device),
            textures: storage(
                "material atlas textures",
                bytemuck::cast_slice(&texture_records),
            ),
            levels: storage(
                "material atlas levels",
                bytemuck::cast_slice(&level_records),
            ),
            texture,
            indices,
            page_size,
        })
    }

    /// The index a shader passes to `atlas_sample` for `key`, if the atlas holds it.
    pub fn index(&self, key: &AtlasKey) -> Option<u32> {
        self.indices.get(key).copied()
    }

    /// Side and layer count of the atlas texture.
    pub fn pages(&self) -> (u32, u32) {
        (self.page_size, self.texture.depth_or_array_layers())
    }

    /// The atlas's bindings of the `material_atlas` library (group 2, bindings 1–5).
    pub fn bind_group_entries(&self) -> [wgpu::BindGroupEntry<'_>; 5] {
        [
            wgpu::BindGroupEntry {
                binding: 1,
                resource: self.textures.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: self.levels.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::TextureView(&self.colour_view),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: wgpu::BindingResource::TextureView(&self.data_view),
            },
            wgpu::BindGroupEntry {
                binding: 5,
                resource: wgpu::BindingResource::Sampler(&self.sampler),
            },
        ]
    }
}

/// Every level of every chain packed into pages of `page_size`² (largest rectangles first
/// packs tightest): how many pages, and where each `(chain, level)` went.
fn pack(
    chains: &[Vec<(u32, u32, Vec<u8>)>],
    page_size: u32,
) -> (u32, HashMap<(usize, usize), Placed>) {
    let mut order: Vec<(usize, usize)> = chains
        .iter()
        .enumerate()
        .flat_map(|(s, levels)| (0..levels.len()).map(move |l| (s, l)))
        .collect();
    order.sort_by_key(|&(s, l)| {
        let (w, h, _) = &chains[s][l];
        std::cmp::Reverse((w + 2) * (h + 2))
    });
    let mut pages: Vec<AtlasAllocator> = Vec::new();
    let mut placed: HashMap<(usize, usize), Placed> = HashMap::new();
    for &(s, l) in &order {
        let (width, height, _) = chains[s][l];
        let size = size2((width + 2) as i32, (height + 2) as i32);
        let spot = pages
            .iter_mut()
            .enumerate()
            .find_map(|(layer, page)| page.allocate(size).map(|a| (layer, a)));
        let (layer, allocation) = match spot {
            Some(found) => found,
            None => {
                let mut page = AtlasAllocator::new(size2(page_size as i32, page_size as i32));
                #[expect(
                    clippy::expect_used,
                    reason = "the page side is at least every rectangle's side"
                )]
                let allocation = page.allocate(size).expect("a rectangle fits an empty page");
                pages.push(page);
                (pages.len() - 1, allocation)
            }
        };
        placed.insert(
            (s, l),
            Placed {
                layer: layer as u32,
                x: allocation.rectangle.min.x as u32,
                y: allocation.rectangle.min.y as u32,
                width,
                height,
            },
        );
    }
    (pages.len() as u32, placed)
}

/// Writes every level with its border, and returns the level records (each set's levels
/// consecutive) and each set's first record.
fn write_levels(
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    level_sets: &[LevelsKey],
    chains: &[Vec<(u32, u32, Vec<u8>)>],
    placed: &HashMap<(usize, usize), Placed>,
    page_size: u32,
) -> (Vec<AtlasLevel>, Vec<u32>) {
    let mut level_records = Vec::new();
    let mut first_level = Vec::with_capacity(level_sets.len());
    for (s, set) in level_sets.iter().enumerate() {
        first_level.push(level_records.len() as u32);
        for (l, (_, _, texels)) in chains[s].iter().enumerate() {
            let p = placed[&(s, l)];
            write_bordered(queue, texture, p, texels, set.repeat_u, set.repeat_v);
            let page = page_size as f32;
            level_records.push(AtlasLevel::new(
                glam::Vec2::new((p.x + 1) as f32, (p.y + 1) as f32) / page,
                glam::Vec2::new(p.width as f32, p.height as f32) / page,
                glam::Vec2::new(p.width as f32, p.height as f32),
                p.layer,
                0,
            ));
        }
    }
    (level_records, first_level)
}

/// One record per distinct key, pointing at its image's levels, and each key's index.
fn texture_records(
    keys: &[AtlasKey],
    level_sets: &[LevelsKey],
    chains: &[Vec<(u32, u32, Vec<u8>)>],
    first_level: &[u32],
) -> (HashMap<AtlasKey, u32>, Vec<AtlasTexture>) {
    let mut indices = HashMap::new();
    let mut texture_records = Vec::new();
    for key in keys {
        let set = level_sets
            .iter()
            .position(|s| *s == levels_key(key))
            .unwrap_or_default();
        indices.entry(*key).or_insert_with(|| {
            let levels = &chains[set];
            let (w, h, _) = levels[0];
            texture_records.push(AtlasTexture::new(
                glam::Vec2::new(w as f32, h as f32),
                first_level[set],
                levels.len() as u32,
                wrap_bits(key.sampler),
                filter_bits(key.sampler),
            ));
            texture_records.len() as u32 - 1
        });
    }
    (indices, texture_records)
}

/// Every distinct set of levels the keys need, in the order the keys first name them (so the
/// packing is deterministic).
fn distinct_level_sets(
    images: &[impl std::borrow::Borrow<Image>],
    keys: &[AtlasKey],
) -> Result<Vec<LevelsKey>, AtlasError> {
    let mut seen = std::collections::HashSet::new();
    let mut sets = Vec::new();
    for key in keys {
        if key.image >= images.len() {
            return Err(AtlasError::UnknownImage {
                image: key.image,
                images: images.len(),
            });
        }
        let set = levels_key(key);
        if seen.insert(set) {
            sets.push(set);
        }
    }
    Ok(sets)
}

/// Bilinear, clamping, level 0 only: the shader picks levels and wraps itself.
fn atlas_sampler(device: &wgpu::Device) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("material atlas"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        lod_max_clamp: 0.0,
        ..Default::default()
    })
}

fn levels_key(key: &AtlasKey) -> LevelsKey {
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
fn stored_levels(image: &Image, colour: bool, max_side: u32) -> Vec<(u32, u32, Vec<u8>)> {
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
fn write_bordered(
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

fn wrap_bits(s: TextureSampler) -> u32 {
    let bits = |w: Wrap| match w {
        Wrap::Repeat => WRAP_REPEAT,
        Wrap::MirroredRepeat => WRAP_MIRROR,
        Wrap::ClampToEdge => WRAP_CLAMP,
    };
    bits(s.wrap_u) | (bits(s.wrap_v) << 2)
}

fn filter_bits(s: TextureSampler) -> u32 {
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
