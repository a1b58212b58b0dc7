//! Tonemapping: the resolved HDR colour through exposure and a filmic curve into the caller's
//! 8-bit sRGB target.

use std::sync::Arc;

use crate::frame::FrameGpu;
use crate::graph::{Handle, RenderGraph, Texture, TextureAccess};

/// Adds the tonemap pass reading `hdr` and writing the imported `output`.
pub fn add(
    graph: &mut RenderGraph,
    gpu: &Arc<FrameGpu>,
    hdr: Handle<Texture>,
    output: &mut Handle<Texture>,
) {
    let target = *output;
    let gpu = Arc::clone(gpu);
    graph
        .add_pass("tonemap")
        .read_texture(hdr, TextureAccess::Sampled)
        .write_texture(output, TextureAccess::ColorAttachment)
        .execute(move |ctx| {
            let hdr_view = ctx.texture(hdr).create_view(&Default::default());
            let out_view = ctx.texture(target).create_view(&Default::default());
            let bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("tonemap"),
                layout: &gpu.pipelines.tonemap_program.bind_group_layouts[0],
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: gpu.tonemap_params.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&hdr_view),
                    },
                ],
            });
            let mut pass = ctx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("tonemap"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &out_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&gpu.pipelines.tonemap);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.draw(0..3, 0..1);
        });
}
