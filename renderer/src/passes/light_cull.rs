//! Light culling: the tiled / 2.5D or clustered kernel over the pre-Z depth, writing the light
//! grid and index list the forward pass reads. The naive path has no culling pass.

use std::sync::Arc;

use crate::frame::{Culler, FrameGpu};
use crate::graph::{Buffer, BufferAccess, Handle, RenderGraph, Texture, TextureAccess};

/// Adds the culling pass reading `depth` and writing `grid` and `indices` (imported).
pub fn add(
    graph: &mut RenderGraph,
    gpu: &Arc<FrameGpu>,
    depth: Handle<Texture>,
    grid: &mut Handle<Buffer>,
    indices: &mut Handle<Buffer>,
) {
    let gpu = Arc::clone(gpu);
    graph
        .add_pass("light culling")
        .read_texture(depth, TextureAccess::Sampled)
        .write_buffer(grid, BufferAccess::StorageWrite)
        .write_buffer(indices, BufferAccess::StorageWrite)
        .execute(move |ctx| {
            let view = ctx.texture(depth).create_view(&Default::default());
            match &gpu.culler {
                Culler::Tiled(c) => c.encode(ctx.device, ctx.encoder, &view),
                Culler::Clustered(c) => c.encode(ctx.device, ctx.encoder, &view),
                Culler::Naive => {}
            }
        });
}
