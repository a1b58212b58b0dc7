//! Depth probe: copies one depth sample per probe point into a buffer, so tools can inspect a
//! frame's depth (see [`crate::frame::capture`]). It runs only in frames a tool asked to capture.

use std::sync::Arc;

use crate::frame::capture::ProbeGpu;
use crate::graph::{Buffer, BufferAccess, Handle, RenderGraph, Texture, TextureAccess};

/// Adds the probe pass reading `depth` and writing the imported `probes` buffer.
pub fn add(
    graph: &mut RenderGraph,
    probe: &Arc<ProbeGpu>,
    depth: Handle<Texture>,
    probes: &mut Handle<Buffer>,
) {
    let probe = Arc::clone(probe);
    graph
        .add_pass("depth probe")
        .read_texture(depth, TextureAccess::Sampled)
        .write_buffer(probes, BufferAccess::StorageWrite)
        .execute(move |ctx| {
            let view = ctx.texture(depth).create_view(&Default::default());
            let bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("depth probe"),
                layout: &probe.kernel.program.bind_group_layouts[0],
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: probe.params.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: probe.output.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::TextureView(&view),
                    },
                ],
            });
            let mut pass = ctx
                .encoder
                .begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("depth probe"),
                    timestamp_writes: None,
                });
            pass.set_pipeline(&probe.kernel.pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            let side = shaders_gen::inspect::depth_probe::WORKGROUP_SIDE;
            pass.dispatch_workgroups(probe.grid.x.div_ceil(side), probe.grid.y.div_ceil(side), 1);
        });
}
