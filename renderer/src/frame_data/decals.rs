//! The frame's decals on the GPU: the records shading reads and the boxes culling tests, both in
//! layer order (the order cell lists keep and shading applies), and the decal atlas's four
//! textures with their sampler. A new set over the same materials keeps the packed atlas and
//! rewrites only the records; one with other materials keeps the atlas too, removed materials'
//! room given back and new ones written into free room, and packs it again only when a new
//! one finds none ([`GpuDecals::updated`]).

use bytemuck::Zeroable as _;
use glam::{Mat4, Vec4};
use shaders_gen::forward::forward::GpuDecal;
use shaders_gen::shared::decal_apply;
use wgpu::util::DeviceExt as _;

use crate::culling::hierarchy::CullBox;
use crate::decals::{
    AtlasEntry, AtlasSpace, Channel, Decal, DecalAtlasConfig, DecalError, DecalMaterial, DecalSet,
    PlacedMaterial,
};

/// Stands for "never" in distance fades (beyond any camera distance, finite in `f32` maths).
const FAR_DISTANCE: f32 = 1.0e30;
/// Steepest fade slope: a fade whose start equals its end is a step.
const STEP_SLOPE: f32 = 1.0e6;

/// Decals uploaded for shading and culling.
#[derive(Debug)]
pub struct GpuDecals {
    /// The decals' boxes for culling, in layer order.
    pub boxes: Vec<CullBox>,
    /// `GpuDecal` records in layer order (one placeholder when there are none).
    pub records: wgpu::Buffer,
    /// Base colour, normal, occlusion-roughness-metalness, emissive ([`Channel`] order).
    pub views: [wgpu::TextureView; Channel::COUNT],
    pub sampler: wgpu::Sampler,
    /// Atlas side in texels and mip levels (1×1 and 1 without decals).
    pub atlas_size: u32,
    pub mip_levels: u32,
    /// What the atlas was packed from and where each material went: a later set with the same
    /// materials and configuration keeps the atlas ([`GpuDecals::updated`]), sharing this
    /// record rather than copying its images.
    packed: Option<std::sync::Arc<Packed>>,
}

/// The materials and configuration an atlas was packed from, its entries, and its room with
/// each material's allocation (to add and remove materials in place).
#[derive(Debug)]
struct Packed {
    materials: Vec<DecalMaterial>,
    config: DecalAtlasConfig,
    entries: Vec<AtlasEntry>,
    space: AtlasSpace,
    allocations: Vec<etagere::AllocId>,
}

/// What `GpuDecals::updated` had to do.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DecalUpload {
    /// The atlas configuration changed, there were no decals, or a new material found no
    /// free room: the atlas was packed and uploaded again.
    Repacked,
    /// Same materials: only the decals' records and boxes were written.
    RecordsOnly,
    /// Materials were added or removed: removed ones gave their room back, new ones were
    /// written into free room (their texels only), the others kept their place; then the
    /// records were written.
    MaterialsInPlace {
        /// Materials written into free room.
        added: usize,
        /// Materials whose room was given back.
        removed: usize,
    },
}

impl GpuDecals {
    /// No decals: a placeholder record and 1×1 textures, so shading binds the same layout.
    pub fn empty(device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
        let neutral = Channel::ALL.map(|c| vec![c.neutral().to_vec()]);
        Self {
            boxes: Vec::new(),
            records: records_buffer(device, &[GpuDecal::zeroed()]),
            views: Channel::ALL.map(|c| upload_channel(device, queue, c, 1, &neutral[c as usize])),
            sampler: sampler(device),
            atlas_size: 1,
            mip_levels: 1,
            packed: None,
        }
    }

    /// [`GpuDecals::new`], keeping `previous`'s atlas when `set` has the same materials and
    /// `config` is the same (decals added, removed or moved over one material palette): then
    /// only the records are written, into `previous`'s buffer where they fit.
    pub fn updated(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        set: &DecalSet,
        config: DecalAtlasConfig,
        previous: &GpuDecals,
    ) -> Result<(Self, DecalUpload), DecalError> {
        let reusable = (previous.packed.as_ref()).filter(|p| p.config == config);
        let Some(old) = reusable.filter(|_| !set.decals.is_empty()) else {
            return Ok((
                Self::new(device, queue, set, config)?,
                DecalUpload::Repacked,
            ));
        };
        set.validate()?;
        check_count(device, set)?;
        let (packed, upload) = if old.materials == set.materials {
            (std::sync::Arc::clone(old), DecalUpload::RecordsOnly)
        } else {
            let Some((packed, placed, removed)) = in_place(old, &set.materials)? else {
                return Ok((
                    Self::new(device, queue, set, config)?,
                    DecalUpload::Repacked,
                ));
            };
            for material in &placed {
                write_material(queue, &previous.views, material);
            }
            let added = placed.len();
            (
                std::sync::Arc::new(packed),
                DecalUpload::MaterialsInPlace { added, removed },
            )
        };
        let order = set.layer_order();
        let records: Vec<GpuDecal> = order
            .iter()
            .map(|&i| record(&set.decals[i], &packed.entries))
            .collect();
        let bytes: &[u8] = bytemuck::cast_slice(&records);
        let records = if previous.records.size() >= bytes.len() as u64 {
            queue.write_buffer(&previous.records, 0, bytes);
            previous.records.clone()
        } else {
            records_buffer(device, &records)
        };
        let gpu = Self {
            boxes: order.iter().map(|&i| cull_box(&set.decals[i])).collect(),
            records,
            views: previous.views.clone(),
            sampler: previous.sampler.clone(),
            atlas_size: previous.atlas_size,
            mip_levels: previous.mip_levels,
            packed: Some(packed),
        };
        Ok((gpu, upload))
    }

    /// Validates `set`, packs its atlas and uploads it with the decals in layer order.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        set: &DecalSet,
        config: DecalAtlasConfig,
    ) -> Result<Self, DecalError> {
        set.validate()?;
        check_count(device, set)?;
        if set.decals.is_empty() {
            return Ok(Self::empty(device, queue));
        }
        let (atlas, space, allocations) = AtlasSpace::build(&set.materials, config)?;
        let order = set.layer_order();
        let records: Vec<GpuDecal> = order
            .iter()
            .map(|&i| record(&set.decals[i], &atlas.entries))
            .collect();
        let boxes = order.iter().map(|&i| cull_box(&set.decals[i])).collect();
        Ok(Self {
            boxes,
            records: records_buffer(device, &records),
            views: Channel::ALL
                .map(|c| upload_channel(device, queue, c, atlas.size, &atlas.levels[c as usize])),
            sampler: sampler(device),
            atlas_size: atlas.size,
            mip_levels: atlas.mip_levels,
            packed: Some(std::sync::Arc::new(Packed {
                materials: set.materials.clone(),
                config,
                entries: atlas.entries,
                space,
                allocations,
            })),
        })
    }

    /// How many decals one storage binding of records holds on `device`.
    pub fn max_decals(device: &wgpu::Device) -> usize {
        crate::gpu::requirements::storage_binding_records(device, size_of::<GpuDecal>()) as usize
    }

    /// Decals uploaded.
    pub fn count(&self) -> u32 {
        self.boxes.len() as u32
    }

    /// The `decal_apply` library's part of every group 0 that shades with decals (its
    /// generated builder: records, the four atlas channels, the sampler).
    pub fn bindings(&self) -> decal_apply::Group0<'_> {
        let [base_color, normal, orm, emissive] = &self.views;
        decal_apply::Group0 {
            decals: self.records.as_entire_buffer_binding(),
            decal_base_color: base_color,
            decal_normal_map: normal,
            decal_orm_map: orm,
            decal_emissive_map: emissive,
            decal_sampler: &self.sampler,
        }
    }
}

/// `old`'s atlas with `materials` in place of its own: each material `old` holds keeps its
/// place, the others' rectangles are given back, and new ones are placed in free room (returned
/// with their texels, to write), with how many were removed; `None` when a new one finds no
/// room.
fn in_place(
    old: &Packed,
    materials: &[DecalMaterial],
) -> Result<Option<(Packed, Vec<PlacedMaterial>, usize)>, DecalError> {
    let mut unused = vec![true; old.materials.len()];
    let kept: Vec<Option<usize>> = (materials.iter())
        .map(|m| {
            let i = (0..old.materials.len()).find(|&i| unused[i] && old.materials[i] == *m)?;
            unused[i] = false;
            Some(i)
        })
        .collect();
    let mut space = old.space.clone();
    let removed = (unused.iter().enumerate()).filter(|&(_, &u)| u);
    let removed = removed
        .map(|(i, _)| space.give_back(old.allocations[i]))
        .count();
    let (mut entries, mut allocations, mut placed) = (Vec::new(), Vec::new(), Vec::new());
    for (m, kept) in materials.iter().zip(kept) {
        if let Some(i) = kept {
            entries.push(old.entries[i]);
            allocations.push(old.allocations[i]);
            continue;
        }
        m.check()?;
        let Some(material) = space.place(m) else {
            return Ok(None);
        };
        entries.push(material.entry);
        allocations.push(material.allocation);
        placed.push(material);
    }
    let packed = Packed {
        materials: materials.to_vec(),
        config: old.config,
        entries,
        space,
        allocations,
    };
    Ok(Some((packed, placed, removed)))
}

/// Writes a material placed in place into the atlas's channel textures, every level of its
/// rectangle.
fn write_material(
    queue: &wgpu::Queue,
    views: &[wgpu::TextureView; Channel::COUNT],
    material: &PlacedMaterial,
) {
    let ((x, y), (width, height)) = (material.corner, material.size);
    for (view, levels) in views.iter().zip(&material.levels) {
        for (level, texels) in levels.iter().enumerate() {
            let (w, h) = (width >> level, height >> level);
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: view.texture(),
                    mip_level: level as u32,
                    origin: wgpu::Origin3d {
                        x: x >> level,
                        y: y >> level,
                        z: 0,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                texels,
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(w * 4),
                    rows_per_image: Some(h),
                },
                wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
            );
        }
    }
}

/// The culling box of a decal: its centre and its axes scaled by the half extents.
pub fn cull_box(decal: &Decal) -> CullBox {
    let m = decal.world_from_box;
    CullBox::new(
        m.w_axis.truncate().extend(1.0),
        (m.x_axis.truncate() * 0.5).extend(0.0),
        (m.y_axis.truncate() * 0.5).extend(0.0),
        (m.z_axis.truncate() * 0.5).extend(0.0),
    )
}

/// [`DecalError::TooMany`] past what one storage binding holds on `device`.
fn check_count(device: &wgpu::Device, set: &DecalSet) -> Result<(), DecalError> {
    let max = GpuDecals::max_decals(device);
    if set.decals.len() > max {
        return Err(DecalError::TooMany {
            count: set.decals.len(),
            max,
        });
    }
    Ok(())
}

/// The shading record of a validated decal, its material at `entries[decal.material]`.
fn record(decal: &Decal, entries: &[AtlasEntry]) -> GpuDecal {
    // World → the unit cube [−0.5, 0.5]³ → [−1, 1]³.
    let box_from_world = Mat4::from_scale(glam::Vec3::splat(2.0)) * decal.world_from_box.inverse();
    let entry = &entries[decal.material];
    let [angle_start, angle_end] = decal.angle_fade;
    let (cos_start, cos_end) = (angle_start.cos(), angle_end.cos());
    let [distance_start, distance_end] = decal.distance_fade.map(|d| d.min(FAR_DISTANCE));
    GpuDecal::new(
        box_from_world.row(0),
        box_from_world.row(1),
        box_from_world.row(2),
        entry.uv,
        Vec4::new(
            cos_end,
            slope(cos_start - cos_end),
            distance_end,
            slope(distance_end - distance_start),
        ),
        decal.blend,
        entry.channels,
    )
}

/// `1 / span`, or a step for an empty span.
fn slope(span: f32) -> f32 {
    if span > 1.0 / STEP_SLOPE {
        1.0 / span
    } else {
        STEP_SLOPE
    }
}

fn records_buffer(device: &wgpu::Device, records: &[GpuDecal]) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("decals"),
        contents: bytemuck::cast_slice(records),
        // COPY_DST: a later set over the same materials is written in place. COPY_SRC: tools
        // read back what a kernel bound (the tests' host replay).
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
    })
}

/// One atlas channel as a texture: `levels[k]` is level `k`, `size >> k` texels square.
fn upload_channel(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    channel: Channel,
    size: u32,
    levels: &[Vec<u8>],
) -> wgpu::TextureView {
    let format = if channel.is_srgb() {
        wgpu::TextureFormat::Rgba8UnormSrgb
    } else {
        wgpu::TextureFormat::Rgba8Unorm
    };
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(channel.name()),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: 1,
        },
        mip_level_count: levels.len() as u32,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        // COPY_SRC: tools read back what a kernel bound (the tests' host replay).
        usage: wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_DST
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    for (level, texels) in levels.iter().enumerate() {
        let side = (size >> level).max(1);
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: level as u32,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            texels,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(side * 4),
                rows_per_image: Some(side),
            },
            wgpu::Extent3d {
                width: side,
                height: side,
                depth_or_array_layers: 1,
            },
        );
    }
    texture.create_view(&Default::default())
}

/// Trilinear, clamped: the atlas's gutters make every level safe to filter. No anisotropy: its
/// longer footprint at grazing angles could reach past a gutter.
fn sampler(device: &wgpu::Device) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("decal atlas"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        ..Default::default()
    })
}
