//! The culling hierarchy every method shares: per-tile depth information and per-super-tile
//! candidate lists (`shaders_gen::culling::cull_prepare`), then a fine kernel (tiled, 2.5D or
//! clustered) that tests only its super-tile's candidates and writes complete lists.
//!
//! This module owns what the levels share: the parameters, the items, the tile-depth and coarse
//! buffers, the output lists, and the three dispatches. [`super::tiled`] and
//! [`super::clustered`] choose the fine kernel and fill in the parameters.

use glam::{Mat4, UVec2, Vec3};
#[cfg(any(test, feature = "internals"))]
pub use shaders_gen::culling::cull_prepare::ITEM_TYPES;
use shaders_gen::culling::cull_prepare::{self, CullParams, Msaa, Tile};
pub use shaders_gen::culling::cull_prepare::{CullBox, CullSphere};
use shaders_gen::shared::cull_append;

use super::CullError;
use super::lists::LightLists;
use crate::GpuContext;
use crate::graph::PassEncoder;
use crate::shader::ShaderProgram;

/// Edge of a super-tile in pixels (`cull_append::SUPER_TILE_PIXELS`).
pub const SUPER_TILE_PIXELS: u32 = cull_prepare::SUPER_TILE_PIXELS;

/// The size-dependent shape of a culling hierarchy.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HierarchyShape {
    /// Tile edge in pixels: 8, 16 or 32.
    pub tile: u32,
    /// MSAA sample count of the depth buffer: 1, 2, 4 or 8.
    pub msaa: u32,
    /// The depths come from the compute rasteriser's buffer ([`DepthInput::Samples`]), not a
    /// depth buffer.
    pub vis64: bool,
    /// Lists per tile (tiled: 1, or 2 with a transparent list; clustered: the depth slices).
    pub lists_per_tile: u32,
    /// Entries the index list holds.
    pub index_capacity: u32,
    /// Items the item buffer holds.
    pub item_capacity: u32,
    /// Skip the super-tile level: every tile tests every item (for comparison).
    pub brute_force: bool,
    /// Candidate slots per super-tile; `None` gives every super-tile room for every item (as far
    /// as one storage binding allows). A super-tile with more candidates than slots falls back
    /// to testing every item: slower, never incomplete.
    pub coarse_slots: Option<u32>,
}

/// Where the culling hierarchy reads the frame's depths.
#[derive(Debug, Clone, Copy)]
pub enum DepthInput<'a> {
    /// A depth buffer of the hierarchy's sample count.
    Texture(&'a wgpu::TextureView),
    /// The compute rasteriser's buffer of samples (`u64` a sample, `(!depth_bits << 32) |
    /// !id`, 0 where no triangle), for a hierarchy of [`HierarchyShape::vis64`].
    Samples(&'a wgpu::Buffer),
}

/// The camera as culling sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CullView {
    pub view: Mat4,
    /// Perspective, or orthographic ([`is_orthographic`]).
    pub projection: Mat4,
    /// Target size in pixels.
    pub screen: UVec2,
}

/// Whether `projection` is orthographic (affine: its last row is `(0, 0, 0, 1)`), so the kernels
/// build tile frustums with parallel sides.
pub fn is_orthographic(projection: &Mat4) -> bool {
    projection.row(3) == glam::Vec4::W
}

/// What one frame culls: the lights as world-space spheres, then the decals as world-space
/// boxes. Item `i < lights.len()` is light `i`; the decals follow, and a cell's decal list
/// holds decal indices in ascending order, so give them in the order they are applied.
#[derive(Debug, Clone, Copy, Default)]
pub struct CullItems<'a> {
    pub lights: &'a [CullSphere],
    pub decals: &'a [CullBox],
}

impl<'a> CullItems<'a> {
    /// Lights only.
    pub fn lights(lights: &'a [CullSphere]) -> Self {
        Self {
            lights,
            decals: &[],
        }
    }

    /// Every item.
    pub fn len(&self) -> usize {
        self.lights.len() + self.decals.len()
    }

    /// Whether there is nothing to cull.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The decals' bounding spheres (around their corners), which follow the lights' in the
    /// item buffer.
    fn box_spheres(&self) -> Vec<CullSphere> {
        self.decals
            .iter()
            .map(|b| {
                let (center, radius) = box_sphere(b);
                CullSphere::new(center, radius)
            })
            .collect()
    }
}

/// A culling box's bounding sphere, through its farthest corner: the sphere the kernels test
/// a decal by before its box.
pub fn box_sphere(b: &CullBox) -> (Vec3, f32) {
    let [x, y, z] = [b.axis_x, b.axis_y, b.axis_z].map(|a| a.truncate());
    let radius = [x + y + z, x + y - z, x - y + z, -x + y + z]
        .into_iter()
        .map(Vec3::length)
        .fold(0.0, f32::max);
    (b.center.truncate(), radius)
}

/// What the fine level's method adds to the parameters.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MethodParams {
    /// Tiled: write a second list per tile for blended surfaces.
    pub transparent: bool,
    /// Clustered: list every depth slice, not only those holding a sample.
    pub all_slices: bool,
    /// Clustered: depth slices (0 for tiled).
    pub slices: u32,
    /// Clustered: view depth where slice 1 starts.
    pub slice_near: f32,
    /// Clustered: view depth where the last slice starts.
    pub slice_far: f32,
}

/// The buffers and pipelines of one culling hierarchy for one target size.
#[derive(Debug)]
pub struct CullHierarchy {
    pub shape: HierarchyShape,
    pub tiles: UVec2,
    pub super_tiles: UVec2,
    /// Candidate slots per super-tile.
    pub coarse_stride: u32,
    pub lists: LightLists,
    prepare: ShaderProgram,
    tile_depth: wgpu::ComputePipeline,
    coarse: wgpu::ComputePipeline,
    fine: ShaderProgram,
    fine_cull: wgpu::ComputePipeline,
    params: wgpu::Buffer,
    items: wgpu::Buffer,
    /// `BOXES`: the decals' boxes.
    boxes: wgpu::Buffer,
    tile_info: wgpu::Buffer,
    /// `COARSE`: the super-tiles' counts and depth ranges, then their candidate slots.
    candidates: wgpu::Buffer,
    /// `SPHERES`: the candidates' view-space spheres, then every item's.
    spheres: wgpu::Buffer,
    /// Items of the last upload (the super-tile pass dispatches one workgroup per chunk).
    item_count: std::sync::atomic::AtomicU32,
}

/// The `cull_prepare` variant key of a tile size and sample count.
fn prepare_key(shape: &HierarchyShape) -> Result<cull_prepare::VariantKey, CullError> {
    let (tile, msaa) = (shape.tile, shape.msaa);
    Ok(cull_prepare::VariantKey {
        tile: Tile::from_value(tile).ok_or(CullError::TileSize(tile))?,
        msaa: Msaa::from_value(msaa).ok_or(CullError::SampleCount(msaa))?,
        vis64: shape.vis64,
    })
}

fn storage(device: &wgpu::Device, label: &str, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(16),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

impl CullHierarchy {
    /// Builds the hierarchy for a `width`×`height` target with `fine` as the last level.
    pub fn new(
        gpu: &GpuContext,
        shape: HierarchyShape,
        fine: &'static codegen::rt::Variant,
        width: u32,
        height: u32,
    ) -> Result<Self, CullError> {
        super::check_index_capacity(gpu.device(), shape.index_capacity)?;
        let device = gpu.device();
        let prepare = gpu.program(cull_prepare::variant(prepare_key(&shape)?))?;
        let fine = gpu.program(fine)?;
        let tiles = UVec2::new(width.div_ceil(shape.tile), height.div_ceil(shape.tile));
        let super_tiles = UVec2::new(
            width.div_ceil(SUPER_TILE_PIXELS),
            height.div_ceil(SUPER_TILE_PIXELS),
        );
        let super_count = super_tiles.x * super_tiles.y;
        // Every super-tile can hold every item, up to what one binding holds; a super-tile with
        // more survivors than its slots falls back to testing every item.
        // Slots hold a sphere (16 bytes) each in `SPHERES`, the largest of the buffers, which
        // also holds every item's sphere after them.
        let binding_spheres = (device.limits().max_storage_buffer_binding_size / 16)
            .saturating_sub(u64::from(shape.item_capacity));
        let per_super =
            u32::try_from(binding_spheres / u64::from(super_count.max(1))).unwrap_or(u32::MAX);
        let coarse_stride = shape
            .coarse_slots
            .unwrap_or(shape.item_capacity)
            .min(per_super)
            .max(1);
        let tile_count = tiles.x * tiles.y;
        Ok(Self {
            lists: LightLists::new(
                device,
                tile_count * shape.lists_per_tile,
                shape.index_capacity,
            ),
            tile_depth: prepare.compute_pipeline(device, "tile_depth")?,
            coarse: prepare.compute_pipeline(device, "coarse_cull")?,
            fine_cull: fine.compute_pipeline(device, "cull")?,
            params: super::uniform_buffer::<CullParams>(device),
            items: storage(
                device,
                "cull items",
                u64::from(shape.item_capacity) * size_of::<CullSphere>() as u64,
            ),
            boxes: storage(
                device,
                "cull boxes",
                u64::from(shape.item_capacity) * size_of::<CullBox>() as u64,
            ),
            tile_info: storage(device, "tile depth", u64::from(tile_count) * 16),
            candidates: storage(
                device,
                "coarse candidates",
                u64::from(super_count) * (4 + u64::from(coarse_stride)) * 4,
            ),
            spheres: storage(
                device,
                "view spheres",
                (u64::from(super_count) * u64::from(coarse_stride)
                    + u64::from(shape.item_capacity))
                    * 16,
            ),
            item_count: std::sync::atomic::AtomicU32::new(0),
            prepare,
            fine,
            shape,
            tiles,
            super_tiles,
            coarse_stride,
        })
    }

    /// The parameters of a frame: the camera, the items and the method's settings.
    pub fn params(&self, camera: &CullView, items: &CullItems, method: MethodParams) -> CullParams {
        CullParams::new(
            camera.view,
            camera.projection,
            camera.projection.inverse(),
            camera.screen,
            self.tiles,
            self.super_tiles,
            items.len() as u32,
            items.lights.len() as u32,
            self.lists.cells,
            self.shape.index_capacity,
            self.coarse_stride,
            u32::from(self.shape.brute_force),
            u32::from(method.transparent),
            u32::from(method.all_slices),
            method.slices,
            method.slice_near,
            method.slice_far,
            u32::from(self.shape.msaa == 1),
            u32::from(is_orthographic(&camera.projection)),
        )
    }

    /// Uploads the parameters, the items' world-space bounding spheres and the decals' boxes.
    pub fn upload(
        &self,
        gpu: &GpuContext,
        params: &CullParams,
        items: &CullItems,
    ) -> Result<(), CullError> {
        super::check_item_count(items.len(), self.shape.item_capacity)?;
        self.item_count
            .store(params.item_count, std::sync::atomic::Ordering::Relaxed);
        gpu.queue()
            .write_buffer(&self.params, 0, bytemuck::bytes_of(params));
        gpu.queue()
            .write_buffer(&self.items, 0, bytemuck::cast_slice(items.lights));
        if !items.decals.is_empty() {
            let after_lights = size_of_val(items.lights) as u64;
            let spheres = items.box_spheres();
            gpu.queue()
                .write_buffer(&self.items, after_lights, bytemuck::cast_slice(&spheres));
            gpu.queue()
                .write_buffer(&self.boxes, 0, bytemuck::cast_slice(items.decals));
        }
        Ok(())
    }

    /// Records the three dispatches reading `depth` (the pre-Z buffer, `shape.msaa` samples, or
    /// the compute rasteriser's samples), in
    /// one compute pass; with `time_dispatches`, each in its own compute pass with its own
    /// timestamps, listed in frame timings as `cull: tile depth`, `cull: super-tiles` and
    /// `cull: tiles`. Separate passes cost time of their own (about 30 µs per frame on the H100
    /// at 1080p), so frames time their dispatches only when asked
    /// (`RendererConfig::time_cull_dispatches`).
    pub fn encode(
        &self,
        device: &wgpu::Device,
        encoder: &mut PassEncoder<'_>,
        depth: DepthInput<'_>,
        time_dispatches: bool,
    ) -> Result<(), shader_bind::BindError> {
        let (prepare, fine) = self.bind_groups(device, depth)?;
        encoder.clear_buffer(&self.lists.counters, 0, None);
        // Counts and depth ranges: four words per super-tile at the start of `COARSE`.
        let counts = u64::from(self.super_tiles.x * self.super_tiles.y) * 16;
        encoder.clear_buffer(&self.candidates, 0, Some(counts));
        let chunks = self
            .item_count
            .load(std::sync::atomic::Ordering::Relaxed)
            .div_ceil(cull_prepare::COARSE_CHUNK);
        let steps = [
            (
                "cull: tile depth",
                &prepare,
                &self.tile_depth,
                self.tiles.extend(1),
            ),
            (
                "cull: super-tiles",
                &prepare,
                &self.coarse,
                self.super_tiles.extend(chunks),
            ),
            ("cull: tiles", &fine, &self.fine_cull, self.tiles.extend(1)),
        ];
        let steps = steps
            .iter()
            .filter(|(name, ..)| !(self.shape.brute_force && *name == "cull: super-tiles"));
        if !time_dispatches {
            // One compute pass: wgpu orders the dispatches by their storage hazards.
            let mut pass = encoder.begin_compute("light cull");
            for (_, bind_group, pipeline, groups) in steps {
                pass.set_bind_group(0, *bind_group, &[]);
                pass.set_pipeline(pipeline);
                pass.dispatch_workgroups(groups.x, groups.y, groups.z);
            }
            return Ok(());
        }
        // A compute pass per dispatch, each with its own timestamps.
        for (name, bind_group, pipeline, groups) in steps {
            let mut pass = encoder.begin_compute_timed(name);
            pass.set_bind_group(0, *bind_group, &[]);
            pass.set_pipeline(pipeline);
            pass.dispatch_workgroups(groups.x, groups.y, groups.z);
        }
        Ok(())
    }

    /// Group 0 of the preparing kernels and of the fine kernel: the `cull_append` library's
    /// part (every culling kernel's buffers), and `depth` where the preparing kernels read it
    /// (given for both spellings; the variant binds the one its MSAA count declares).
    fn bind_groups(
        &self,
        device: &wgpu::Device,
        depth: DepthInput<'_>,
    ) -> Result<(wgpu::BindGroup, wgpu::BindGroup), shader_bind::BindError> {
        let lists = cull_append::Group0 {
            params: self.params.as_entire_buffer_binding(),
            items: self.items.as_entire_buffer_binding(),
            grid: self.lists.grid.as_entire_buffer_binding(),
            indices: self.lists.indices.as_entire_buffer_binding(),
            counters: self.lists.counters.as_entire_buffer_binding(),
            tile_depth: self.tile_info.as_entire_buffer_binding(),
            coarse: self.candidates.as_entire_buffer_binding(),
            spheres: self.spheres.as_entire_buffer_binding(),
            boxes: self.boxes.as_entire_buffer_binding(),
        };
        let (texture, samples) = match depth {
            DepthInput::Texture(view) => (Some(view), None),
            DepthInput::Samples(buffer) => (None, Some(buffer.as_entire_buffer_binding())),
        };
        let prepare = cull_prepare::Group0 {
            depth: texture,
            depth_ms: texture,
            vis64: samples,
            cull_append: lists.clone(),
        }
        .bind_group(
            device,
            self.prepare.layout(0),
            self.prepare.variant,
            "cull: prepare",
        )?;
        // The fine kernel (`tile_cull` or `cluster_cull`) binds the library's part alone.
        let fine = shader_bind::Resources::of(&lists).build(
            device,
            self.fine.layout(0),
            self.fine.variant,
            0,
            "cull: fine",
        )?;
        Ok((prepare, fine))
    }

    /// Takes a new index capacity for the next frame (at most what one storage binding holds;
    /// beyond that, overflow stays counted).
    pub fn grow(&mut self, device: &wgpu::Device, index_capacity: u32) {
        let index = index_capacity.min(super::max_index_entries(device));
        if index != self.shape.index_capacity {
            self.shape.index_capacity = index;
            self.lists = LightLists::new(device, self.lists.cells, index);
        }
    }
}
