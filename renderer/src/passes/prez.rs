//! Depth pre-pass: every opaque and masked draw into the MSAA depth buffer, so culling sees the
//! scene's depth and forward shading runs once per visible sample. Masked materials discard
//! texels below their cutoff here too, so they leave no depth where they are see-through.

use std::sync::Arc;

use crate::frame::FrameGpu;
use crate::graph::{Handle, RenderGraph, Texture, TextureAccess, TextureDesc};
use crate::scene::AlphaMode;

pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Adds the pre-Z pass; returns the depth buffer it writes.
pub fn add(
    graph: &mut RenderGraph,
    gpu: &Arc<FrameGpu>,
    width: u32,
    height: u32,
) -> Handle<Texture> {
    let mut depth = graph.create_texture(
        "depth",
        TextureDesc::new_2d(width, height, DEPTH_FORMAT).with_samples(gpu.msaa),
    );
    let target = depth;
    let gpu = Arc::clone(gpu);
    graph
        .add_pass("pre-z")
        .write_texture(&mut depth, TextureAccess::DepthWrite)
        .execute(move |ctx| {
            let view = ctx.texture(target).create_view(&Default::default());
            let mut pass = ctx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("pre-z"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &gpu.prez_camera, &[]);
            let scene = &gpu.scene;
            for draw in &scene.draws {
                let material = &scene.materials[draw.material];
                // Blended surfaces must not hide what is behind them.
                if material.alpha_mode == AlphaMode::Blend {
                    continue;
                }
                match &material.prez_mask_group {
                    Some(mask) => {
                        pass.set_pipeline(gpu.pipelines.prez_mask(material.double_sided));
                        pass.set_bind_group(2, mask, &[]);
                    }
                    None => pass.set_pipeline(gpu.pipelines.prez(material.double_sided)),
                }
                pass.set_bind_group(1, &draw.bind_group, &[]);
                let p = &scene.gpu.meshes[draw.mesh][draw.primitive];
                super::draw_primitive(&mut pass, p, &[&p.positions, &p.uvs]);
            }
        });
    depth
}
