//! The visibility path's samples as the passes of a frame hand them on
//! ([`crate::frame_data::FrameResources::visibility`]).

use crate::graph::{Buffer, Handle, Texture};

#[cfg(doc)]
use crate::frame_data::FrameResources;

/// Where a frame's visibility samples are: per sample, the ID of the scene triangle it sees
/// (the `vis_geometry` library's numbering) and its depth.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VisibilitySamples {
    /// The hardware raster's: an `R32Uint` target, multisampled with the frame, beside
    /// [`FrameResources::depth`]. The target is loaded, not cleared: where the depth is 1.0 a
    /// sample sees no triangle and its ID is meaningless (0, or what an earlier frame left).
    /// Read it only where the depth is below 1.0.
    Targets {
        /// The IDs.
        ids: Handle<Texture>,
    },
    /// The compute rasteriser's ([`crate::frame_data::VisibilityRaster::Compute`]): a storage
    /// buffer of one `u64` a sample, `(y × width + x) × msaa + s`, holding
    /// `(!depth_bits << 32) | !id`, or 0 where no triangle covers the sample. The alpha-masked
    /// draws are in it too. [`FrameResources::depth`] is then a depth target resolved from it,
    /// by a pass the graph leaves out unless a pass reads that target: the renderer's own
    /// passes (shading, light culling, occlusion culling, blended surfaces, particles) read
    /// the buffer.
    Buffer {
        /// The samples.
        samples: Handle<Buffer>,
    },
}

/// The visibility buffer of a frame (`passes::visibility`).
#[derive(Debug, Clone)]
pub struct VisibilityHandles {
    /// The samples' IDs and depths.
    pub samples: VisibilitySamples,
    /// Where each draw's triangles are (`vis_geometry`'s `DRAW_GEOMETRY`), in draw order.
    pub draw_geometry: wgpu::Buffer,
    /// Draws in `draw_geometry`.
    pub draws: u32,
    /// The sequence index buffer (index `i` is `i`): a pass that pulls its vertices
    /// (`vis_geometry`'s `pulled_vertex`) draws the scene's indexed draws over it.
    pub sequence: wgpu::Buffer,
}
