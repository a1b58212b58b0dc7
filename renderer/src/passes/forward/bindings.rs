//! Group 0 of the `forward` module's programs, which the forward pass and the G-buffer pass
//! (the module's `fs_gbuffer`) both bind: camera, lighting uniform, lights, the light and decal
//! lists when culled, the shadow atlas (6–8) and the decals (9–14).

use std::sync::Arc;

use shaders_gen::forward::forward;

use crate::frame_data::{
    FrameInputs, GpuDecals, LightListHandles, LightSet, ListGeometry, ShadowResources,
};
use crate::graph::PassContext;

/// The frame's lighting uniform: light counts and the geometry of `lists`.
pub(crate) fn lighting_uniform(
    frame: &FrameInputs,
    lists: Option<&LightListHandles>,
) -> forward::Lighting {
    let c = &frame.config;
    let g = ListGeometry::new(lists.map(|l| l.method), c, &frame.camera);
    forward::Lighting::new(
        c.ambient.sky,
        frame.lights.punctual.len() as u32,
        c.ambient.ground,
        g.tiles,
        g.tile,
        g.slices,
        g.blend_cell_offset,
        g.near,
        g.far,
        frame.lights.directional.len() as u32,
        frame.decals.count(),
        g.decal_section,
    )
}

/// What group 0 binds, captured for a pass's recording.
pub(crate) struct FrameGroup {
    camera: wgpu::Buffer,
    lighting: wgpu::Buffer,
    lights: Arc<LightSet>,
    decals: Arc<GpuDecals>,
    lists: Option<LightListHandles>,
    shadows: ShadowResources,
}

impl FrameGroup {
    /// Writes `lighting` for this frame and captures the rest of group 0.
    pub(crate) fn new(
        frame: &FrameInputs,
        lighting: &wgpu::Buffer,
        lists: Option<LightListHandles>,
        shadows: ShadowResources,
    ) -> Self {
        let uniform = lighting_uniform(frame, lists.as_ref());
        frame
            .gpu
            .queue
            .write_buffer(lighting, 0, bytemuck::bytes_of(&uniform));
        Self {
            camera: frame.camera_uniform.buffer.clone(),
            lighting: lighting.clone(),
            lights: Arc::clone(&frame.lights),
            decals: Arc::clone(&frame.decals),
            lists,
            shadows,
        }
    }

    /// The bind group, on `layout` (group 0 of a `forward` variant).
    pub(crate) fn bind_group(
        &self,
        ctx: &PassContext<'_>,
        layout: &wgpu::BindGroupLayout,
        label: &str,
    ) -> wgpu::BindGroup {
        let mut resources = vec![
            self.camera.as_entire_binding(),
            self.lighting.as_entire_binding(),
            self.lights.punctual_buffer.as_entire_binding(),
            self.lights.directional_buffer.as_entire_binding(),
        ];
        if let Some(l) = &self.lists {
            resources.push(ctx.buffer(l.grid).as_entire_binding());
            resources.push(ctx.buffer(l.indices).as_entire_binding());
        }
        let mut entries = super::super::entries(&resources);
        entries.extend(self.shadows.entries());
        entries.extend(self.decals.entries());
        ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout,
            entries: &entries,
        })
    }
}

/// A `forward` lighting uniform buffer.
pub(crate) fn lighting_buffer(device: &wgpu::Device) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("lighting"),
        size: size_of::<forward::Lighting>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
