//! Group 0 of the `forward` module's programs, which the forward pass and the G-buffer pass
//! (the module's `fs_gbuffer`) both bind: camera, lighting uniform, lights, the light and decal
//! lists when culled, and the `shadow_atlas` and `decal_apply` libraries' parts, bound through
//! the module's generated builder (`forward::Group0`).

use std::sync::Arc;

use shaders_gen::forward::{forward, material_frame};
use shaders_gen::visibility::vis_shade;

use crate::frame_data::{
    FrameInputs, GpuDecals, LightListHandles, LightSet, ListGeometry, ShadowResources,
};
use crate::graph::PassContext;
use crate::shader::ShaderProgram;

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
            .queue()
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

    /// Group 0 of `program` (a `forward` variant), through the module's generated builder;
    /// `None` after recording the error in `ctx` ([`PassContext::bind`]).
    pub(crate) fn bind_group(
        &self,
        ctx: &mut PassContext<'_>,
        program: &ShaderProgram,
        label: &str,
    ) -> Option<wgpu::BindGroup> {
        let group = forward::Group0 {
            material_frame: material_frame::Group0 {
                camera: self.camera.as_entire_buffer_binding(),
                lighting: self.lighting.as_entire_buffer_binding(),
            },
            light_set: self.lights.bindings(),
            light_lists: LightListHandles::bindings(self.lists.as_ref(), ctx),
            shadow_atlas: self.shadows.bindings(),
            decal_apply: self.decals.bindings(),
        }
        .bind_group(
            ctx.device,
            program.layout(forward::Group0::GROUP),
            program.variant,
            label,
        );
        ctx.bind(group)
    }
}

impl FrameGroup {
    /// Group 0 of `program`, a `vis_shade` variant: this frame group's parts, the kernel's
    /// parameters `vis`, the visibility buffer `ids` and the HDR output `out`; `None` after
    /// recording the error in `ctx`.
    pub(crate) fn vis_bind_group(
        &self,
        ctx: &mut PassContext<'_>,
        program: &ShaderProgram,
        vis: &wgpu::Buffer,
        ids: &wgpu::TextureView,
        out: &wgpu::TextureView,
    ) -> Option<wgpu::BindGroup> {
        let builder = vis_shade::Group0 {
            vis: vis.as_entire_buffer_binding(),
            ids: Some(ids),
            ids_ms: Some(ids),
            hdr_out: out,
            material_frame: material_frame::Group0 {
                camera: self.camera.as_entire_buffer_binding(),
                lighting: self.lighting.as_entire_buffer_binding(),
            },
            light_set: self.lights.bindings(),
            light_lists: LightListHandles::bindings(self.lists.as_ref(), ctx),
            shadow_atlas: self.shadows.bindings(),
            decal_apply: self.decals.bindings(),
        };
        let group = program.bind_group(
            ctx.device,
            vis_shade::Group0::GROUP,
            &shader_bind::Resources::of(&builder),
            "visibility shading",
        );
        ctx.bind(group)
    }
}

/// A `forward` lighting uniform buffer.
pub(crate) fn lighting_buffer(device: &wgpu::Device) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("lighting"),
        size: size_of::<forward::Lighting>() as u64,
        // COPY_SRC: tools read back what a kernel bound (the tests' host replay).
        usage: wgpu::BufferUsages::UNIFORM
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}
