//! Forward shading: PBR over the chosen light list into the MSAA HDR target, resolved to a
//! single-sample HDR texture. Opaque draws first, then blended draws back to front.

use std::sync::Arc;

use crate::frame::FrameGpu;
use crate::graph::{
    Buffer, BufferAccess, Handle, RenderGraph, Texture, TextureAccess, TextureDesc,
};
use crate::scene::AlphaMode;

pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Adds the forward pass; returns the resolved HDR colour. With `depth` from a pre-pass it tests
/// against it; with `None` (naive forward without pre-Z) it clears and writes its own.
pub fn add(
    graph: &mut RenderGraph,
    gpu: &Arc<FrameGpu>,
    depth: Option<Handle<Texture>>,
    lists: Option<(Handle<Buffer>, Handle<Buffer>)>,
    width: u32,
    height: u32,
) -> Handle<Texture> {
    let msaa = gpu.msaa;
    let mut hdr = graph.create_texture("hdr", TextureDesc::new_2d(width, height, HDR_FORMAT));
    let mut hdr_msaa = (msaa > 1).then(|| {
        graph.create_texture(
            "hdr msaa",
            TextureDesc::new_2d(width, height, HDR_FORMAT).with_samples(msaa),
        )
    });
    let (resolved, multisampled) = (hdr, hdr_msaa);
    let prepass = depth.is_some();
    let mut own_depth = depth.is_none().then(|| {
        let desc = TextureDesc::new_2d(width, height, super::prez::DEPTH_FORMAT).with_samples(msaa);
        graph.create_texture("depth", desc)
    });
    let depth_target = depth.or(own_depth).expect("one of the two is set");
    let gpu = Arc::clone(gpu);
    let mut pass = graph.add_pass("forward");
    match (depth, own_depth.as_mut()) {
        (Some(d), _) => pass.read_texture(d, TextureAccess::DepthRead),
        (None, Some(d)) => pass.write_texture(d, TextureAccess::DepthWrite),
        (None, None) => &mut pass,
    };
    pass.write_texture(&mut hdr, TextureAccess::ColorAttachment);
    if let Some(h) = hdr_msaa.as_mut() {
        pass.write_texture(h, TextureAccess::ColorAttachment);
    }
    if let Some((grid, indices)) = lists {
        pass.read_buffer(grid, BufferAccess::StorageRead)
            .read_buffer(indices, BufferAccess::StorageRead);
    }
    pass.execute(move |ctx| {
        let depth_view = ctx.texture(depth_target).create_view(&Default::default());
        let resolved_view = ctx.texture(resolved).create_view(&Default::default());
        let msaa_view = multisampled.map(|h| ctx.texture(h).create_view(&Default::default()));
        let frame_group = gpu.forward_frame_group(ctx.device);
        let mut pass = ctx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("forward"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: msaa_view.as_ref().unwrap_or(&resolved_view),
                depth_slice: None,
                resolve_target: msaa_view.as_ref().map(|_| &resolved_view),
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(gpu.clear_color),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: if prepass {
                        wgpu::LoadOp::Load
                    } else {
                        wgpu::LoadOp::Clear(1.0)
                    },
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &frame_group, &[]);
        let scene = &gpu.scene;
        let eye = gpu.eye;
        let mut order: Vec<usize> = (0..scene.draws.len()).collect();
        // Opaque and masked first (any order), then blended back to front.
        order.sort_by(|&a, &b| {
            let (da, db) = (&scene.draws[a], &scene.draws[b]);
            let blend = |d: &crate::frame::DrawItem| {
                scene.materials[d.material].alpha_mode == AlphaMode::Blend
            };
            blend(da).cmp(&blend(db)).then_with(|| {
                if blend(da) {
                    db.center
                        .distance_squared(eye)
                        .total_cmp(&da.center.distance_squared(eye))
                } else {
                    std::cmp::Ordering::Equal
                }
            })
        });
        for i in order {
            let draw = &scene.draws[i];
            let material = &scene.materials[draw.material];
            let blend = material.alpha_mode == AlphaMode::Blend;
            pass.set_pipeline(gpu.pipelines.forward(blend, material.double_sided));
            pass.set_bind_group(1, &draw.bind_group, &[]);
            pass.set_bind_group(2, &material.bind_group, &[]);
            let p = &scene.gpu.meshes[draw.mesh][draw.primitive];
            super::draw_primitive(
                &mut pass,
                p,
                &[&p.positions, &p.normals, &p.uvs, &p.tangents],
            );
        }
    });
    hdr
}
