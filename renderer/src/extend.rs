//! What a pass an engine inserts into the frame sees
//! ([`Renderer::insert_pass_after`](crate::frame::Renderer::insert_pass_after)).
//!
//! A pass implements [`Pass`]: each frame it reads the frame's inputs ([`FrameInputs`]: camera,
//! scene, lights, configuration) and declares its work on the frame graph
//! ([`crate::graph::RenderGraph`]), reading what earlier passes left in [`FrameResources`]
//! (the depth and HDR targets, the light lists, the shadow atlas, the G-buffer, particles) and
//! adding what it produces. Bind the renderer's resources through the generated bind-group
//! builders of `shaders_gen`, as [`LightListHandles::bindings`] and
//! [`ShadowResources::bindings`] do.

pub use crate::frame_data::{
    DEPTH_FORMAT, FrameInputs, FrameResources, GBUFFER_FORMATS, GBufferHandles, HDR_FORMAT,
    LightListHandles, ListGeometry, OverlayEraser, ParticleResources, ShadowResources,
    VisibilityHandles, VisibilitySamples,
};
pub use crate::passes::Pass;
/// A built-in pass to insert after `"visibility"` on the visibility path: the compute
/// rasteriser, which rasterises the same opaque triangles with 64-bit atomics beside the
/// raster pass, to measure it and compare its IDs (that frame does not read them). With
/// [`crate::frame_data::VisibilityRaster::Compute`] the visibility raster pass runs it itself,
/// and the frame's timings name its graph passes `"compute raster"`,
/// [`COMPUTE_RASTER_TILES_PASS`] and, under occlusion culling, [`COMPUTE_RASTER_LATE_PASS`]
/// and [`COMPUTE_RASTER_LATE_TILES_PASS`].
pub use crate::passes::visibility::{
    COMPUTE_RASTER_LATE_PASS, COMPUTE_RASTER_LATE_TILES_PASS, COMPUTE_RASTER_TILES_PASS,
    ComputeRasterCounts, ComputeRasterPass, DEFAULT_SMALL_AREA,
};
