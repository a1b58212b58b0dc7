//! The visibility-buffer path ([`crate::frame::RenderPath::Visibility`]): a raster pass writes
//! depth and, per sample, the ID of the scene triangle it sees (`raster`); a compute pass finds
//! each pixel's triangles again, evaluates their materials and lights them through the frame's
//! light lists (`shade`). It replaces pre-Z and the G-buffer: 4 bytes a sample besides depth.
//! `compute_raster` rasterises the opaque triangles in compute instead
//! ([`crate::frame_data::VisibilityRaster::Compute`]; the raster pass then merges only the
//! alpha-masked draws into its buffer, which every pass of the frame reads, and `resolve`
//! writes a depth target from it for a pass that reads one), or beside the raster pass, to
//! measure and check that way of rasterising.

mod compute_raster;
mod compute_raster_buffers;
pub(crate) mod geometry;
mod raster;
mod raster_draws;
pub(crate) mod resolve;
mod shade;

pub use compute_raster::{
    ComputeRasterCounts, ComputeRasterPass, DEFAULT_SMALL_AREA,
    LATE_PASS as COMPUTE_RASTER_LATE_PASS, LATE_TILES_PASS as COMPUTE_RASTER_LATE_TILES_PASS,
    TILES_PASS as COMPUTE_RASTER_TILES_PASS,
};
pub use raster::VisRasterPass;
pub use shade::VisShadePass;
