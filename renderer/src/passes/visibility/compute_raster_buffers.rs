//! The compute rasteriser's buffers (`super::compute_raster`): what one screen size and scene
//! size need, sized from the frame, and checked against the device's binding size.

use shaders_gen::visibility::compute_raster::vis_compute_raster as kernels;

use std::sync::Weak;

use crate::frame_data::{BatchLayout, ConfigError, FrameInputs, RenderError};

/// Tiles listed per screen tile before large triangles overflow.
const ITEMS_PER_SCREEN_TILE: u64 = 32;
/// Large triangles listed at most (80 bytes each).
const LARGE_CAPACITY: u32 = 1 << 18;
/// Large triangles listed at most when every triangle is large (`small_area` 0).
const LARGE_CAPACITY_TILES_ONLY: u32 = 1 << 20;

/// The buffers of one screen size and scene size.
#[derive(Debug)]
pub(super) struct Buffers {
    /// What they were made for.
    pub(super) sizing: Sizing,
    pub(super) vis64: wgpu::Buffer,
    pub(super) counters: wgpu::Buffer,
    pub(super) large: wgpu::Buffer,
    pub(super) items: wgpu::Buffer,
    pub(super) tile_args: wgpu::Buffer,
    /// `tile_args` copied, for the indirect dispatches.
    pub(super) indirect: wgpu::Buffer,
    pub(super) classes: wgpu::Buffer,
    /// `raster_triangles`' chunks (written with `classes`), and how many are listed.
    pub(super) chunks: wgpu::Buffer,
    pub(super) chunk_count: u32,
    /// The batch layout and instance revision `classes` was written for (held weakly: a
    /// dropped layout never matches a new one at the same address).
    pub(super) classes_of: Option<(Weak<BatchLayout>, u64)>,
}

fn storage(
    device: &wgpu::Device,
    label: &str,
    size: u64,
    extra: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(16),
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC
            | extra,
        mapped_at_creation: false,
    })
}

/// A frame's sizes: what the buffers are made for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Sizing {
    pub(super) samples: u64,
    /// Scene triangles: IDs run over every draw's triangles, in draw order (`vis_geometry`).
    pub(super) triangles: u32,
    pub(super) large_capacity: u32,
    pub(super) item_capacity: u32,
    pub(super) draws: usize,
    /// Chunks of every draw's triangles: the most `CHUNKS` lists.
    pub(super) chunk_capacity: u32,
}

impl Sizing {
    pub(super) fn of(frame: &FrameInputs, msaa: u32, small_area: u32) -> Self {
        let c = &frame.config;
        let (triangles, chunk_capacity) =
            frame
                .instances
                .draws
                .iter()
                .fold((0u32, 0u32), |(n, c), d| {
                    let t = d.geometry.index_count / 3;
                    let chunks = t.div_ceil(kernels::TRIANGLE_WORKGROUP);
                    (n.saturating_add(t), c.saturating_add(chunks))
                });
        let screen_tiles = u64::from(c.width.div_ceil(kernels::TILE))
            * u64::from(c.height.div_ceil(kernels::TILE));
        // Every triangle is large where `small_area` is 0: room for each and its tiles.
        let (large_most, per_triangle) = if small_area == 0 {
            (LARGE_CAPACITY_TILES_ONLY, 4)
        } else {
            (LARGE_CAPACITY, 0)
        };
        let items = screen_tiles * ITEMS_PER_SCREEN_TILE
            + u64::from(triangles.min(large_most)) * per_triangle;
        Self {
            samples: u64::from(c.width) * u64::from(c.height) * u64::from(msaa),
            triangles,
            large_capacity: triangles.clamp(1, large_most),
            item_capacity: u32::try_from(items).unwrap_or(u32::MAX),
            draws: frame.instances.draws.len(),
            chunk_capacity,
        }
    }
}

impl Sizing {
    /// Fails with [`ConfigError::BufferTooLarge`] where a buffer is over the device's binding
    /// size.
    pub(super) fn check(&self, device: &wgpu::Device) -> Result<(), RenderError> {
        let max = device.limits().max_storage_buffer_binding_size;
        let large = size_of::<kernels::LargeTriangle>() as u64;
        let buffers = [
            ("samples", self.samples * 8),
            ("large-triangle", u64::from(self.large_capacity) * large),
            ("tile item", u64::from(self.item_capacity) * 8),
            ("chunk", u64::from(self.chunk_capacity) * 8),
        ];
        match buffers.into_iter().find(|&(_, bytes)| bytes > max) {
            Some((buffer, bytes)) => Err(RenderError::Config(ConfigError::BufferTooLarge {
                pass: "compute raster",
                buffer,
                bytes,
                max,
            })),
            None => Ok(()),
        }
    }
}

impl Buffers {
    pub(super) fn new(device: &wgpu::Device, sizing: Sizing) -> Self {
        let none = wgpu::BufferUsages::empty();
        let large_bytes = size_of::<kernels::LargeTriangle>() as u64;
        Self {
            sizing,
            vis64: storage(device, "compute raster samples", sizing.samples * 8, none),
            counters: storage(device, "compute raster counters", 16, none),
            large: storage(
                device,
                "compute raster large",
                u64::from(sizing.large_capacity) * large_bytes,
                none,
            ),
            items: storage(
                device,
                "compute raster items",
                u64::from(sizing.item_capacity) * 8,
                none,
            ),
            tile_args: storage(device, "compute raster tile args", 32, none),
            indirect: storage(
                device,
                "compute raster indirect dispatches",
                32,
                wgpu::BufferUsages::INDIRECT,
            ),
            classes: storage(
                device,
                "compute raster classes",
                sizing.draws.max(1) as u64 * 4,
                none,
            ),
            chunks: storage(
                device,
                "compute raster chunks",
                u64::from(sizing.chunk_capacity.max(1)) * 8,
                none,
            ),
            chunk_count: 0,
            classes_of: None,
        }
    }
}
