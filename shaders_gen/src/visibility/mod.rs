//! The visibility-buffer path's GPU code: the raster pass that writes, per sample, the depth and
//! a 32-bit ID of the scene triangle it sees (`vis_raster`), and the geometry those IDs name,
//! read back in compute (`vis_geometry`), and the materials and lighting of what the samples see,
//! in compute (`vis_shade`).

pub mod geometry;
pub mod raster;
pub mod shade;

pub use raster::vis_raster;
pub use shade::vis_shade;
