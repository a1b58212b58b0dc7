//! Exactly the features and limits the renderer asks of a device.
//!
//! Nothing is required beyond WebGPU's defaults; optional features are requested only when the
//! adapter has them, and limits are raised only as far as the renderer uses them and the adapter
//! allows. Code that needs an optional feature checks [`super::Capabilities`] first.

use super::error::{GpuError, MissingLimit};

/// Features the renderer uses when present.
pub const OPTIONAL_FEATURES: wgpu::Features = wgpu::Features::SUBGROUP
    .union(wgpu::Features::TIMESTAMP_QUERY)
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS)
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES)
    // MSAA 2 and 8, and multisampled Rgba16Float beyond the WebGPU guarantee.
    .union(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES)
    // Indirect draws that find their draw record by instance index (GPU-culled scenes); without
    // it the geometry passes draw each slot directly.
    .union(wgpu::Features::INDIRECT_FIRST_INSTANCE)
    // Multi-draws whose count the GPU writes: shadow casters culled per region are packed and
    // counted, so a region draws only what reaches it.
    .union(wgpu::Features::MULTI_DRAW_INDIRECT_COUNT)
    // 64-bit integers and their atomic min/max on storage buffers: the compute rasteriser
    // (`passes::visibility::compute_raster`) packs depth and triangle ID into one atomic.
    .union(wgpu::Features::SHADER_INT64)
    .union(wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX)
    // The variant's own SPIR-V given to a Vulkan driver where wgpu's would be invalid (a
    // `sample_mask` built-in: `crate::shader`).
    .union(wgpu::Features::PASSTHROUGH_SHADERS);

/// Largest compute workgroup the kernels use: a 32×32 tile, one invocation per pixel.
pub const WANTED_WORKGROUP_INVOCATIONS: u32 = 32 * 32;
/// Largest storage binding the light lists use (index lists for 65,536 lights at 4K).
pub const WANTED_STORAGE_BINDING_BYTES: u64 = 1 << 30;

/// How many `element_size`-byte records one storage binding holds on `device`: the smaller of
/// its storage-binding and buffer size limits, divided by the record size.
pub fn storage_binding_records(device: &wgpu::Device, element_size: usize) -> u64 {
    let limits = device.limits();
    let bytes = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    bytes / element_size as u64
}

/// Storage buffers one shader stage binds at most: the particle lighting kernel's ten (the
/// light lists and shadow views, and the particle records, layout and output). Above the
/// WebGPU default of 8; every Vulkan, Metal and D3D12 desktop adapter has at least 16.
pub const STORAGE_BUFFERS_PER_STAGE: u32 = 10;

/// Storage buffers per stage the renderer asks for where the adapter has them: the visibility
/// path's shading kernels bind 19 (the light lists, shadow views and decals, the draw records,
/// the material table and atlas, the scene's index and vertex streams, and the pixel sums the
/// kernels pass on), a material program's 20 with its parameter records, 21 over the compute
/// rasteriser's samples (a storage buffer where the hardware raster's are two textures). A
/// device with fewer runs every other path; the visibility path is then refused by name, and
/// [`crate::frame::VisibilityRaster::Auto`] takes the hardware raster below 21.
pub const WANTED_STORAGE_BUFFERS_PER_STAGE: u32 = 21;

/// The smallest storage binding and buffer the renderer is tested with: it sizes its light
/// lists, lights and scene buffers to the device's limits (with typed errors where something
/// does not fit), so it runs below WebGPU's 128 MiB default.
pub const SMALLEST_STORAGE_BINDING_BYTES: u64 = 128 << 10;

/// The least a device must allow for every path of the renderer: WebGPU's default limits, with
/// [`STORAGE_BUFFERS_PER_STAGE`] storage buffers per stage above them and storage bindings and
/// buffers down to [`SMALLEST_STORAGE_BINDING_BYTES`] below them. [`for_adapter`] asks at least
/// this; an engine that opens its own device must too ([`super::GpuContext::from_parts`] checks
/// it).
pub fn minimum_limits() -> wgpu::Limits {
    wgpu::Limits {
        max_storage_buffers_per_shader_stage: STORAGE_BUFFERS_PER_STAGE,
        max_storage_buffer_binding_size: SMALLEST_STORAGE_BINDING_BYTES,
        max_buffer_size: SMALLEST_STORAGE_BINDING_BYTES,
        ..wgpu::Limits::default()
    }
}

/// Every limit of `limits` (a device's) that is worse than [`minimum_limits`], in
/// `wgpu::Limits` field order; empty when the renderer can run on it.
pub fn missing_limits(limits: &wgpu::Limits) -> Vec<MissingLimit> {
    let mut missing = vec![];
    minimum_limits().check_limits_with_fail_fn(limits, false, |limit, needed, available| {
        missing.push(MissingLimit {
            limit,
            needed,
            available,
        });
    });
    missing
}

/// The optional features this adapter has.
pub fn optional_features(adapter: &wgpu::Adapter) -> wgpu::Features {
    adapter.features() & OPTIONAL_FEATURES
}

/// The workgroup size the device will allow: what the kernels want, capped by the adapter.
pub fn workgroup_invocations(adapter: &wgpu::Adapter) -> u32 {
    adapter
        .limits()
        .max_compute_invocations_per_workgroup
        .min(WANTED_WORKGROUP_INVOCATIONS)
}

/// The features and limits to request from `adapter`.
pub fn for_adapter(adapter: &wgpu::Adapter) -> Result<(wgpu::Features, wgpu::Limits), GpuError> {
    let have = adapter.limits();
    let base = wgpu::Limits::default();
    // The WebGPU defaults are the floor: an adapter below them cannot run the renderer.
    let floor: [(&'static str, u64, u64); 3] = [
        (
            "max_compute_invocations_per_workgroup",
            base.max_compute_invocations_per_workgroup.into(),
            have.max_compute_invocations_per_workgroup.into(),
        ),
        (
            "max_storage_buffers_per_shader_stage",
            STORAGE_BUFFERS_PER_STAGE.into(),
            have.max_storage_buffers_per_shader_stage.into(),
        ),
        (
            "max_storage_buffer_binding_size",
            base.max_storage_buffer_binding_size,
            have.max_storage_buffer_binding_size,
        ),
    ];
    if let Some((limit, needed, available)) = floor.into_iter().find(|(_, n, a)| a < n) {
        return Err(GpuError::InsufficientLimit {
            adapter: adapter.get_info().name,
            limit,
            needed,
            available,
        });
    }
    let invocations = workgroup_invocations(adapter);
    let limits = wgpu::Limits {
        max_compute_invocations_per_workgroup: invocations,
        max_compute_workgroup_size_x: have.max_compute_workgroup_size_x.min(invocations),
        max_compute_workgroup_size_y: have.max_compute_workgroup_size_y.min(invocations),
        max_storage_buffer_binding_size: have
            .max_storage_buffer_binding_size
            .min(WANTED_STORAGE_BINDING_BYTES),
        max_buffer_size: have.max_buffer_size.min(WANTED_STORAGE_BINDING_BYTES),
        max_storage_buffers_per_shader_stage: have
            .max_storage_buffers_per_shader_stage
            .min(WANTED_STORAGE_BUFFERS_PER_STAGE),
        ..base
    }
    .using_resolution(have.clone())
    .using_alignment(have);
    Ok((optional_features(adapter), limits))
}
