//! The material atlas, host side of `shaders_gen::shared::material_atlas`: every mip level of
//! every material texture packed with `etagere` into the layers of one 2D array texture, each
//! level at its own rectangle inside a one-texel border that holds what the texture's wrap mode
//! puts beside the edge. A shader reaches a texture by its index ([`MaterialAtlas::index`]), so
//! one bind group serves every material, on WebGPU as on Vulkan.
//!
//! Levels are shared by every texture of one image whose borders agree (the same image, as
//! colour or data, repeating or not along each axis; mirrored repeat and clamp borders are the
//! same), so an image sampled by two samplers is stored once unless their borders differ.
//!
//! The atlas grows in place ([`MaterialAtlas::add`]): a new image's levels go into the free
//! space of the pages, or into new layers (the texture made again with the old layers copied
//! on the GPU), and every texture held keeps its index; only an image larger than a page needs
//! the atlas packed anew. Textures no material samples any more are released
//! ([`MaterialAtlas::release`]): their rectangles and records are taken by later additions.

mod levels;
mod release;

use std::collections::HashMap;

use etagere::{AtlasAllocator, size2};
use shaders_gen::shared::material_atlas::{self, AtlasLevel, AtlasTexture};
use wgpu::util::DeviceExt as _;

pub use levels::AtlasKey;

use super::Image;
use super::free_ranges::FreeRanges;
use levels::{
    Level, LevelsKey, Placed, filter_bits, levels_key, stored_levels, wrap_bits, write_bordered,
};

/// What the atlas cannot hold.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum AtlasError {
    /// An [`AtlasKey::image`] is past the images given.
    #[error("material texture names image {image}, but the scene has {images} images")]
    UnknownImage {
        /// The image index asked for.
        image: usize,
        /// How many images were given.
        images: usize,
    },
    /// The packed textures need more array layers than the device's
    /// `max_texture_array_layers`.
    #[error(
        "the material textures need {layers} atlas layers of {size}×{size} texels; the device \
         allows {limit} (fewer or smaller images are needed)"
    )]
    TooManyLayers {
        /// Layers needed.
        layers: u32,
        /// The side of one layer (page), in texels.
        size: u32,
        /// The device's `max_texture_array_layers`.
        limit: u32,
    },
}

/// What [`MaterialAtlas::add`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AtlasGrowth {
    /// Every texture was held already: nothing changed.
    Held,
    /// The new textures were stored; the atlas's buffers and views are new, so bind groups
    /// holding [`MaterialAtlas::bindings`] must be made again.
    Grown,
    /// A new image's largest level does not fit a page: nothing changed, and the atlas must be
    /// packed anew with every texture ([`MaterialAtlas::new`]).
    NeedsRepack,
}

/// A stored set of levels: its first level record, how many, level 0's size, and each
/// level's rectangle (layer and allocation).
#[derive(Debug, Clone)]
struct StoredSet {
    first_level: u32,
    levels: u32,
    size: (u32, u32),
    rectangles: Vec<(u32, etagere::AllocId)>,
}

/// The pages' allocators, one per layer (etagere's have no `Debug`).
#[derive(Clone, Default)]
struct Pages(Vec<AtlasAllocator>);

impl std::fmt::Debug for Pages {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} pages", self.0.len())
    }
}

/// Every material texture of a scene in one array texture, with the records the shader reads.
#[derive(Debug, Clone)]
pub struct MaterialAtlas {
    texture: wgpu::Texture,
    colour_view: wgpu::TextureView,
    data_view: wgpu::TextureView,
    sampler: wgpu::Sampler,
    textures: wgpu::Buffer,
    levels: wgpu::Buffer,
    indices: HashMap<AtlasKey, u32>,
    page_size: u32,
    pages: Pages,
    sets: HashMap<LevelsKey, StoredSet>,
    level_records: Vec<AtlasLevel>,
    texture_records: Vec<AtlasTexture>,
    /// Level records that sets no longer held gave back, and texture records of released
    /// textures: new ones take them first.
    level_space: FreeRanges,
    free_textures: Vec<u32>,
    /// Times textures were added in place since the atlas was packed.
    additions: u32,
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
        let max_side = device.limits().max_texture_dimension_2d;
        let new_sets = distinct_level_sets(images, keys, &HashMap::new())?;
        let chains = chains(images, &new_sets, max_side);
        let widest = chains
            .iter()
            .flat_map(|levels| levels.first())
            .map(|(w, h, _)| (*w).max(*h) + 2)
            .max()
            .unwrap_or(1);
        let page_size = widest.next_power_of_two().clamp(MIN_PAGE, max_side);
        let mut pages = Pages::default();
        let placed = place(&mut pages.0, &chains, page_size);
        let layers = checked_layers(device, &pages, page_size)?;
        let texture = atlas_texture(device, page_size, layers);
        let mut atlas = Self {
            colour_view: view(&texture, wgpu::TextureFormat::Rgba8UnormSrgb),
            data_view: view(&texture, wgpu::TextureFormat::Rgba8Unorm),
            sampler: atlas_sampler(device),
            textures: records_buffer::<AtlasTexture>(device, "material atlas textures", &[]),
            levels: records_buffer::<AtlasLevel>(device, "material atlas levels", &[]),
            texture,
            indices: HashMap::new(),
            page_size,
            pages,
            sets: HashMap::new(),
            level_records: Vec::new(),
            texture_records: Vec::new(),
            level_space: FreeRanges::new(0, 0),
            free_textures: Vec::new(),
            additions: 0,
        };
        atlas.store(device, queue, keys, &new_sets, &chains, &placed);
        Ok(atlas)
    }

    /// Adds the textures of `keys` the atlas does not hold yet, in place: new images' levels
    /// go where the pages have room, else into new layers; every texture held keeps its index.
    /// On an error, or [`AtlasGrowth::NeedsRepack`], nothing changed.
    pub fn add(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        images: &[impl std::borrow::Borrow<Image>],
        keys: &[AtlasKey],
    ) -> Result<AtlasGrowth, AtlasError> {
        let new_sets = distinct_level_sets(images, keys, &self.sets)?;
        if keys.iter().all(|k| self.indices.contains_key(k)) {
            return Ok(AtlasGrowth::Held);
        }
        let max_side = device.limits().max_texture_dimension_2d;
        let chains = chains(images, &new_sets, max_side);
        let fits = |(w, h, _): &Level| (*w).max(*h) + 2 <= self.page_size;
        if !chains.iter().flat_map(|c| c.first()).all(fits) {
            return Ok(AtlasGrowth::NeedsRepack);
        }
        let mut pages = self.pages.clone();
        let placed = place(&mut pages.0, &chains, self.page_size);
        let layers = checked_layers(device, &pages, self.page_size)?;
        let held = self.texture.depth_or_array_layers();
        if layers > held {
            // A texture with more layers, the old ones copied over on the GPU (submitted now,
            // so the new levels written below land after the copy).
            let texture = atlas_texture(device, self.page_size, layers);
            let mut encoder = device.create_command_encoder(&Default::default());
            encoder.copy_texture_to_texture(
                self.texture.as_image_copy(),
                texture.as_image_copy(),
                wgpu::Extent3d {
                    width: self.page_size,
                    height: self.page_size,
                    depth_or_array_layers: held,
                },
            );
            queue.submit([encoder.finish()]);
            self.colour_view = view(&texture, wgpu::TextureFormat::Rgba8UnormSrgb);
            self.data_view = view(&texture, wgpu::TextureFormat::Rgba8Unorm);
            self.texture = texture;
        }
        self.pages = pages;
        self.store(device, queue, keys, &new_sets, &chains, &placed);
        self.additions += 1;
        Ok(AtlasGrowth::Grown)
    }

    /// Writes the levels of `new_sets` where `placed` put them, records every key not held,
    /// and uploads the records.
    fn store(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        keys: &[AtlasKey],
        new_sets: &[LevelsKey],
        chains: &[Vec<Level>],
        placed: &HashMap<(usize, usize), Placed>,
    ) {
        let page = self.page_size as f32;
        for (s, set) in new_sets.iter().enumerate() {
            let first_level = self.take_level_records(chains[s].len());
            let mut rectangles = Vec::with_capacity(chains[s].len());
            for (l, (_, _, texels)) in chains[s].iter().enumerate() {
                let p = placed[&(s, l)];
                write_bordered(queue, &self.texture, p, texels, set.repeat_u, set.repeat_v);
                rectangles.push((p.layer, p.allocation));
                self.level_records[first_level as usize + l] = AtlasLevel::new(
                    glam::Vec2::new((p.x + 1) as f32, (p.y + 1) as f32) / page,
                    glam::Vec2::new(p.width as f32, p.height as f32) / page,
                    glam::Vec2::new(p.width as f32, p.height as f32),
                    p.layer,
                    0,
                );
            }
            let stored = StoredSet {
                first_level,
                levels: chains[s].len() as u32,
                size: chains[s].first().map_or((1, 1), |(w, h, _)| (*w, *h)),
                rectangles,
            };
            self.sets.insert(*set, stored);
        }
        for key in keys {
            if self.indices.contains_key(key) {
                continue;
            }
            let Some(set) = self.sets.get(&levels_key(key)) else {
                continue;
            };
            let record = AtlasTexture::new(
                glam::Vec2::new(set.size.0 as f32, set.size.1 as f32),
                set.first_level,
                set.levels,
                wrap_bits(key.sampler),
                filter_bits(key.sampler),
            );
            let index = match self.free_textures.pop() {
                Some(index) => {
                    self.texture_records[index as usize] = record;
                    index
                }
                None => {
                    self.texture_records.push(record);
                    self.texture_records.len() as u32 - 1
                }
            };
            self.indices.insert(*key, index);
        }
        self.textures = records_buffer(device, "material atlas textures", &self.texture_records);
        self.levels = records_buffer(device, "material atlas levels", &self.level_records);
    }

    /// The index a shader passes to `atlas_sample` for `key`, if the atlas holds it.
    pub fn index(&self, key: &AtlasKey) -> Option<u32> {
        self.indices.get(key).copied()
    }

    /// How many times [`MaterialAtlas::add`] stored new textures in place since the atlas was
    /// packed.
    pub fn additions(&self) -> u32 {
        self.additions
    }

    /// Side and layer count of the atlas texture.
    pub fn pages(&self) -> (u32, u32) {
        (self.page_size, self.texture.depth_or_array_layers())
    }

    /// The `material_atlas` library's part of every group 2 that samples material textures
    /// (its generated builder: texture and level records, the colour and data views, the
    /// sampler).
    pub fn bindings(&self) -> material_atlas::Group2<'_> {
        material_atlas::Group2 {
            atlas_textures: self.textures.as_entire_buffer_binding(),
            atlas_levels: self.levels.as_entire_buffer_binding(),
            atlas_colour: &self.colour_view,
            atlas_data: &self.data_view,
            atlas_sampler: &self.sampler,
        }
    }
}

/// The layers `pages` need, at least one, if the device allows them.
fn checked_layers(device: &wgpu::Device, pages: &Pages, size: u32) -> Result<u32, AtlasError> {
    let layers = (pages.0.len() as u32).max(1);
    let limit = device.limits().max_texture_array_layers;
    if layers > limit {
        return Err(AtlasError::TooManyLayers {
            layers,
            size,
            limit,
        });
    }
    Ok(layers)
}

/// Each set's stored levels: the chain from the first level that fits the device.
fn chains(
    images: &[impl std::borrow::Borrow<Image>],
    sets: &[LevelsKey],
    max_side: u32,
) -> Vec<Vec<Level>> {
    sets.iter()
        .map(|set| stored_levels(images[set.image].borrow(), set.colour, max_side))
        .collect()
}

/// Every level of every chain placed in `pages` of `page_size`² (largest rectangles first
/// packs tightest), new pages added where none has room: where each `(chain, level)` went.
fn place(
    pages: &mut Vec<AtlasAllocator>,
    chains: &[Vec<Level>],
    page_size: u32,
) -> HashMap<(usize, usize), Placed> {
    let mut order: Vec<(usize, usize)> = chains
        .iter()
        .enumerate()
        .flat_map(|(s, levels)| (0..levels.len()).map(move |l| (s, l)))
        .collect();
    order.sort_by_key(|&(s, l)| {
        let (w, h, _) = &chains[s][l];
        std::cmp::Reverse((w + 2) * (h + 2))
    });
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
                allocation: allocation.id,
            },
        );
    }
    placed
}

/// Every distinct set of levels the keys need that `stored` lacks, in the order the keys
/// first name them (so the packing is deterministic).
fn distinct_level_sets(
    images: &[impl std::borrow::Borrow<Image>],
    keys: &[AtlasKey],
    stored: &HashMap<LevelsKey, StoredSet>,
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
        if !stored.contains_key(&set) && seen.insert(set) {
            sets.push(set);
        }
    }
    Ok(sets)
}

/// The atlas's array texture: `layers` pages of `page_size`², RGBA8 (viewed as sRGB for
/// colour).
fn atlas_texture(device: &wgpu::Device, page_size: u32, layers: u32) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
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
        usage: wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_DST
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[wgpu::TextureFormat::Rgba8UnormSrgb],
    })
}

fn view(texture: &wgpu::Texture, format: wgpu::TextureFormat) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        label: Some("material atlas"),
        format: Some(format),
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

/// A storage buffer of `records` (one zeroed record when there are none: storage buffers are
/// never empty).
fn records_buffer<T: bytemuck::Pod + bytemuck::Zeroable>(
    device: &wgpu::Device,
    label: &str,
    records: &[T],
) -> wgpu::Buffer {
    let zero = [T::zeroed()];
    let contents = if records.is_empty() {
        &zero[..]
    } else {
        records
    };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(contents),
        // COPY_SRC: tools read back what a kernel bound (the tests' host replay).
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
    })
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
