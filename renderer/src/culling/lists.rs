//! The output every culling method shares: a grid of `(offset, count)` per cell and item type
//! (lights, then decals), one index list with a capacity and a guard region, and the overflow
//! counters.

use glam::UVec2;
use shaders_gen::culling::cull_prepare::ITEM_TYPES;
use wgpu::util::DeviceExt as _;

use crate::{GpuContext, GpuError, readback};

/// Word written past the index capacity, to prove kernels never write there.
pub const GUARD_WORD: u32 = 0xDEAD_BEEF;
/// Words of guard region after the index capacity.
pub const GUARD_WORDS: u32 = 64;

/// Overflow counters of one culling dispatch (the kernels' `COUNTERS` buffer, in order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CullCounters {
    /// Index-list entries requested by all cells (may exceed the capacity).
    pub requested_entries: u32,
    /// Super-tiles whose candidates did not fit their slots, so their tiles tested every item
    /// (slower, still complete).
    pub coarse_fallbacks: u32,
    /// Entries dropped because the index list was full (the host grows it for the next frame).
    pub dropped: u32,
    /// The longest list written.
    pub max_cell_items: u32,
}

impl CullCounters {
    pub const WORDS: u64 = 4;

    pub fn from_words(c: &[u32]) -> Self {
        Self {
            requested_entries: c[0],
            coarse_fallbacks: c[1],
            dropped: c[2],
            max_cell_items: c[3],
        }
    }
}

/// The grid, index list and counters read back from the GPU.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CullReadback {
    /// `(offset, count)` per cell: the light lists of every cell, then the decal lists.
    pub grid: Vec<UVec2>,
    /// The whole index buffer, guard region included.
    pub indices: Vec<u32>,
    pub counters: CullCounters,
}

impl CullReadback {
    /// Cells per item type (the decal list of cell `c` is grid entry `cells() + c`).
    pub fn cells(&self) -> usize {
        self.grid.len() / ITEM_TYPES as usize
    }

    /// Grid entry `e`'s entries, in the order the GPU wrote them.
    fn entries(&self, e: usize) -> &[u32] {
        let UVec2 {
            x: offset,
            y: count,
        } = self.grid[e];
        &self.indices[offset as usize..(offset + count) as usize]
    }

    /// The sorted light list of cell `c`.
    pub fn cell_items(&self, c: usize) -> Vec<u32> {
        let mut items = self.entries(c).to_vec();
        items.sort_unstable();
        items
    }

    /// Every cell's sorted light list.
    pub fn all_lists(&self) -> Vec<Vec<u32>> {
        (0..self.cells()).map(|c| self.cell_items(c)).collect()
    }

    /// The decal list of cell `c` as written: decal indices, in the order shading applies them
    /// (ascending).
    pub fn cell_decals(&self, c: usize) -> &[u32] {
        self.entries(self.cells() + c)
    }

    /// Every cell's decal list, as written.
    pub fn all_decal_lists(&self) -> Vec<Vec<u32>> {
        (0..self.cells())
            .map(|c| self.cell_decals(c).to_vec())
            .collect()
    }
}

/// GPU buffers of a culling result.
#[derive(Debug)]
pub struct LightLists {
    /// Cells per item type; the grid holds `ITEM_TYPES` entries per cell.
    pub cells: u32,
    pub index_capacity: u32,
    pub grid: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub counters: wgpu::Buffer,
}

impl LightLists {
    pub fn new(device: &wgpu::Device, cells: u32, index_capacity: u32) -> Self {
        let usage = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST;
        let guarded: Vec<u32> = vec![GUARD_WORD; (index_capacity + GUARD_WORDS) as usize];
        Self {
            cells,
            index_capacity,
            grid: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("light grid"),
                size: u64::from(cells.max(1)) * 8 * u64::from(ITEM_TYPES),
                usage,
                mapped_at_creation: false,
            }),
            indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("light indices"),
                contents: bytemuck::cast_slice(&guarded),
                usage,
            }),
            counters: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("cull counters"),
                size: CullCounters::WORDS * 4,
                usage,
                mapped_at_creation: false,
            }),
        }
    }

    /// Bytes of the grid and of the usable index list.
    pub fn bytes(&self) -> (u64, u64) {
        (
            u64::from(self.cells) * 8 * u64::from(ITEM_TYPES),
            u64::from(self.index_capacity) * 4,
        )
    }

    /// Blocking readback (tests and tools).
    pub fn read_back(&self, gpu: &GpuContext) -> Result<CullReadback, GpuError> {
        let grid = readback::read_buffer::<UVec2>(gpu.device(), gpu.queue(), &self.grid)?;
        let indices = readback::read_buffer::<u32>(gpu.device(), gpu.queue(), &self.indices)?;
        let counters = readback::read_buffer::<u32>(gpu.device(), gpu.queue(), &self.counters)?;
        Ok(CullReadback {
            grid: grid[..(self.cells * ITEM_TYPES) as usize].to_vec(),
            indices,
            counters: CullCounters::from_words(&counters),
        })
    }
}
