//! The render passes, one module each. Every pass is a free function that adds itself to a
//! [`crate::graph::RenderGraph`], declaring what it reads and writes, and returns the handles of
//! what it produces. Their GPU state lives in [`crate::frame::FrameGpu`].

pub mod depth_probe;
pub mod forward;
pub mod heatmap;
pub mod light_cull;
pub mod prez;
pub mod tonemap;

/// Draws `primitive` of `mesh` with the given vertex streams bound to slots 0.. in order.
pub(crate) fn draw_primitive<'a>(
    pass: &mut wgpu::RenderPass<'a>,
    primitive: &'a crate::scene::GpuPrimitive,
    streams: &[&'a wgpu::Buffer],
) {
    for (slot, buffer) in streams.iter().enumerate() {
        pass.set_vertex_buffer(slot as u32, buffer.slice(..));
    }
    pass.set_index_buffer(primitive.indices.slice(..), wgpu::IndexFormat::Uint32);
    pass.draw_indexed(0..primitive.index_count, 0, 0..1);
}

/// A vertex buffer layout of one tightly packed attribute at `location`.
pub(crate) fn stream(location: u32, format: wgpu::VertexFormat) -> [wgpu::VertexAttribute; 1] {
    [wgpu::VertexAttribute {
        format,
        offset: 0,
        shader_location: location,
    }]
}
