//! Group 0 of the `forward` module's programs, which the forward pass and the G-buffer pass
//! (the module's `fs_gbuffer`) both bind: camera, lighting uniform, lights, the light and decal
//! lists when culled, and the `shadow_atlas` and `decal_apply` libraries' parts, bound through
//! the module's generated builder (`forward::Group0`).

use std::sync::Arc;

use shaders_gen::forward::{forward, material_frame};
use shaders_gen::visibility::{vis_blend, vis_frame};

use crate::frame_data::{
    FrameInputs, GpuDecals, LightListHandles, LightSet, ListGeometry, ShadowResources,
};
use crate::graph::{PassBuilder, PassContext, TextureAccess};
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
#[derive(Clone)]
pub(crate) struct FrameGroup {
    camera: wgpu::Buffer,
    lighting: wgpu::Buffer,
    lights: Arc<LightSet>,
    decals: Arc<GpuDecals>,
    lists: Option<LightListHandles>,
    shadows: ShadowResources,
}

impl FrameGroup {
    /// Declares what group 0 reads from the frame graph: the light lists and the shadow atlas.
    pub(crate) fn read_by(&self, pass: &mut PassBuilder<'_>) {
        LightListHandles::read_by(self.lists.as_ref(), pass);
        pass.read_texture(self.shadows.atlas, TextureAccess::Sampled);
    }

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

    /// Group 0 of `program` (a forward variant of glTF PBR's or a material program's), through
    /// the module's generated builder, with the program's parameter records `params` where it
    /// takes them; `None` after recording the error in `ctx` ([`PassContext::bind`]).
    pub(crate) fn bind_group(
        &self,
        ctx: &mut PassContext<'_>,
        (program, params): (&ShaderProgram, Option<&wgpu::Buffer>),
        label: &str,
    ) -> Option<wgpu::BindGroup> {
        // The visibility kernels' own inputs: not in the forward variants.
        let vis = vis_frame::Group0 {
            vis: None,
            ids: None,
            ids_ms: None,
            vis64: None,
            hdr_out: None,
            accum: None,
            vis_depth: None,
            vis_depth_ms: None,
        };
        self.build(ctx, (program, params), (vis, NO_BLEND_LISTS), label)
    }

    /// Group 0 of `program`, a material program's visibility kernel (`vis_shade`): this frame
    /// group's parts, the kernel's own inputs and its parameter records `params` where it takes
    /// them; `None` after recording the error in `ctx`.
    pub(crate) fn vis_bind_group(
        &self,
        ctx: &mut PassContext<'_>,
        (program, params): (&ShaderProgram, Option<&wgpu::Buffer>),
        vis: &VisInputs<'_>,
    ) -> Option<wgpu::BindGroup> {
        let (ids, depth, samples) = match vis.samples {
            VisSampleViews::Targets { ids, depth } => (Some(ids), Some(depth), None),
            VisSampleViews::Buffer(samples) => (None, None, Some(samples)),
        };
        let inputs = vis_frame::Group0 {
            vis: Some(vis.params.as_entire_buffer_binding()),
            ids,
            ids_ms: ids,
            vis64: samples.map(wgpu::Buffer::as_entire_buffer_binding),
            hdr_out: Some(vis.out),
            accum: Some(vis.sums.as_entire_buffer_binding()),
            vis_depth: depth,
            vis_depth_ms: depth,
        };
        self.build(
            ctx,
            (program, params),
            (inputs, NO_BLEND_LISTS),
            "visibility shading",
        )
    }

    /// Group 0 of `program`, glTF PBR's blended variant over the compute rasteriser's
    /// samples (`vis_blend`): this frame group's parts, the `VisParams` uniform `params`, the
    /// `samples`, and the blended fragments' lists and records; `None` after recording the
    /// error in `ctx`.
    pub(crate) fn over_samples_bind_group(
        &self,
        ctx: &mut PassContext<'_>,
        program: &ShaderProgram,
        (params, [samples, lists, records]): (&wgpu::Buffer, &[wgpu::Buffer; 3]),
    ) -> Option<wgpu::BindGroup> {
        let inputs = vis_frame::Group0 {
            vis: Some(params.as_entire_buffer_binding()),
            ids: None,
            ids_ms: None,
            vis64: Some(samples.as_entire_buffer_binding()),
            hdr_out: None,
            accum: None,
            vis_depth: None,
            vis_depth_ms: None,
        };
        let blend = vis_blend::Group0 {
            blend_lists: Some(lists.as_entire_buffer_binding()),
            blend_records: Some(records.as_entire_buffer_binding()),
        };
        self.build(
            ctx,
            (program, None),
            (inputs, blend),
            "blended over samples",
        )
    }

    fn build(
        &self,
        ctx: &mut PassContext<'_>,
        (program, params): (&ShaderProgram, Option<&wgpu::Buffer>),
        (vis, blend): (vis_frame::Group0<'_>, vis_blend::Group0<'_>),
        label: &str,
    ) -> Option<wgpu::BindGroup> {
        let builder = forward::Group0 {
            material_frame: material_frame::Group0 {
                camera: self.camera.as_entire_buffer_binding(),
                lighting: self.lighting.as_entire_buffer_binding(),
            },
            vis_frame: vis,
            vis_blend: blend,
            light_set: self.lights.bindings(),
            light_lists: LightListHandles::bindings(self.lists.as_ref(), ctx),
            shadow_atlas: self.shadows.bindings(),
            decal_apply: self.decals.bindings(),
        };
        let mut resources = shader_bind::Resources::of(&builder);
        if let Some(params) = params {
            resources.push(
                crate::materials::PARAMS_NAME,
                Some(shader_bind::Resource::Buffer(
                    params.as_entire_buffer_binding(),
                )),
            );
        }
        let group = program.bind_group(ctx.device, forward::Group0::GROUP, &resources, label);
        ctx.bind(group)
    }
}

/// The blended fragments' lists and records: only the blended variant over the compute
/// rasteriser's samples binds them.
const NO_BLEND_LISTS: vis_blend::Group0<'static> = vis_blend::Group0 {
    blend_lists: None,
    blend_records: None,
};

/// The visibility kernels' own inputs of group 0 ([`FrameGroup::vis_bind_group`]).
pub(crate) struct VisInputs<'a> {
    /// The kernel's `VisParams` uniform.
    pub params: &'a wgpu::Buffer,
    /// The visibility samples.
    pub samples: &'a VisSampleViews,
    /// The HDR output.
    pub out: &'a wgpu::TextureView,
    /// The per-pixel sums the kernels pass on.
    pub sums: &'a wgpu::Buffer,
}

/// Where a visibility shading kernel reads its samples (`VisibilitySamples`, recorded).
pub(crate) enum VisSampleViews {
    /// The raster's ID target and its depth (1.0: sky, whatever the ID).
    Targets {
        ids: wgpu::TextureView,
        depth: wgpu::TextureView,
    },
    /// The compute rasteriser's buffer (the `vis64` variants).
    Buffer(wgpu::Buffer),
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
