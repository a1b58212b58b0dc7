//! The visibility-buffer path's GPU code: the raster pass that writes, per sample, the depth and
//! a 32-bit ID of the scene triangle it sees (`vis_raster`), and the geometry those IDs name,
//! read back in compute (`vis_geometry`), and the frame of the materials' kernels that shade
//! and light what the samples see, in compute (`vis_frame`; each material's `vis_shade`). The
//! compute rasteriser (`vis_compute_raster`) rasterises the same triangles with 64-bit atomics,
//! and `vis_resolve` writes its samples into the depth and visibility buffers; `vis64_sample`
//! reads one of its samples. `vis_blend` lights the blended surfaces drawn over the compute
//! rasteriser's frame in compute.

pub mod blend;
pub mod compute_raster;
pub mod frame;
pub mod geometry;
pub mod raster;
pub mod resolve;
pub mod samples64;

pub use blend::vis_blend;
pub use compute_raster::vis_compute_raster;
pub use frame::vis_frame;
pub use raster::vis_raster;
pub use resolve::vis_resolve;
pub use samples64::vis64_sample;
