//! Light-count heatmap debug view: each pixel coloured by how many lights its tile or froxel
//! lists (reference 000's "Visualize Light Count"), with a legend strip along the bottom.

use std::sync::Arc;

use crate::frame::FrameGpu;
use crate::graph::{Buffer, BufferAccess, Handle, RenderGraph, Texture, TextureAccess};

/// Adds the heatmap pass reading the light lists (and, for clusters, the depth) and writing the
/// imported `output`.
pub fn add(
    graph: &mut RenderGraph,
    gpu: &Arc<FrameGpu>,
    depth: Handle<Texture>,
    (grid, indices): (Handle<Buffer>, Handle<Buffer>),
    output: &mut Handle<Texture>,
) {
    let target = *output;
    let gpu = Arc::clone(gpu);
    let Some(heatmap) = gpu.pipelines.heatmap.as_ref().map(|h| h.needs_depth) else {
        return;
    };
    let mut pass = graph.add_pass("light heatmap");
    pass.read_buffer(grid, BufferAccess::StorageRead)
        .read_buffer(indices, BufferAccess::StorageRead)
        .write_texture(output, TextureAccess::ColorAttachment);
    if heatmap {
        pass.read_texture(depth, TextureAccess::Sampled);
    }
    pass.execute(move |ctx| {
        let Some(h) = gpu.pipelines.heatmap.as_ref() else {
            return;
        };
        let depth_view = ctx.texture(depth).create_view(&Default::default());
        let out_view = ctx.texture(target).create_view(&Default::default());
        let lists = gpu.lists();
        let mut entries = vec![
            wgpu::BindGroupEntry {
                binding: 0,
                resource: gpu.heatmap_params.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: lists.grid.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: lists.indices.as_entire_binding(),
            },
        ];
        if h.needs_depth {
            entries.push(wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::TextureView(&depth_view),
            });
        }
        let bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("light heatmap"),
            layout: &h.program.bind_group_layouts[0],
            entries: &entries,
        });
        let mut pass = ctx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("light heatmap"),
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
        pass.set_pipeline(&h.pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.draw(0..3, 0..1);
    });
}
