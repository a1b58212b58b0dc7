//! Light culling: which lights (and later decals and probes) can touch each screen tile or
//! froxel cluster.
//!
//! The GPU kernels live in `shaders_gen::culling`; this module holds their host side: the
//! hierarchy every method shares ([`hierarchy`]: tile depth, super-tile candidates, the fine
//! dispatch), the methods ([`tiled`], [`clustered`]), the output they share ([`lists`]), overflow
//! readback and index-list growth ([`overflow`]), the types both speak ([`vocabulary`]), and the
//! independent CPU reference ([`reference`]) that the kernels are proven against.

pub mod capacity;
pub mod clustered;
pub mod depth;
pub mod hierarchy;
pub mod lists;
pub mod overflow;
#[cfg(any(test, feature = "internals"))]
pub mod reference;
pub mod tiled;
pub mod vocabulary;

#[cfg(any(test, feature = "internals"))]
pub use vocabulary::SUPER_TILE_PIXELS;
pub use vocabulary::{ClusterGrid, CullCamera, LightSphere, Method, Plane};

use crate::GpuError;
use crate::shader::VariantError;

/// Why light culling cannot be set up or run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CullError {
    #[error("tile size {0} is not supported; use 8, 16 or 32")]
    TileSize(u32),
    #[error("MSAA sample count {0} is not supported; use 1, 2, 4 or 8")]
    SampleCount(u32),
    #[error(
        "the cluster grid needs 1 to 32 depth slices, a tile size of 8, 16 or 32 and \
         0 < near < far, got {0}"
    )]
    Grid(String),
    #[error(
        "{count} items do not fit the item buffer of {capacity}; create the culling pass with a \
         larger item_capacity"
    )]
    TooManyItems { count: usize, capacity: u32 },
    #[error(
        "an index list of {entries} entries does not fit one storage binding on this device (at \
         most {max_entries}); use a smaller index capacity, fewer lights, or the 2.5D or \
         clustered method, which list fewer entries"
    )]
    IndexListTooLarge { entries: u32, max_entries: u32 },
    #[error(transparent)]
    Variant(#[from] VariantError),
    #[error(transparent)]
    Gpu(#[from] GpuError),
}

/// The most index-list entries one storage binding holds on `device` (guard region included).
pub fn max_index_entries(device: &wgpu::Device) -> u32 {
    let words = device.limits().max_storage_buffer_binding_size / 4;
    u32::try_from(words)
        .unwrap_or(u32::MAX)
        .saturating_sub(lists::GUARD_WORDS)
}

fn check_index_capacity(device: &wgpu::Device, entries: u32) -> Result<(), CullError> {
    let max_entries = max_index_entries(device);
    if entries > max_entries {
        return Err(CullError::IndexListTooLarge {
            entries,
            max_entries,
        });
    }
    Ok(())
}

fn check_item_count(count: usize, capacity: u32) -> Result<(), CullError> {
    if count > capacity as usize {
        return Err(CullError::TooManyItems { count, capacity });
    }
    Ok(())
}

fn uniform_buffer<T>(device: &wgpu::Device) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("cull params"),
        size: size_of::<T>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
