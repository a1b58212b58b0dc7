//! The visibility path's shading pass: materials and lighting in compute
//! (`shaders_gen`'s `vis_shade`), over the light lists, writing the resolved HDR image.

use shaders_gen::visibility::vis_shade;

use super::geometry::geometry_group;
use crate::GpuContext;
use crate::frame_data::{
    ConfigError, FrameInputs, FrameResources, FrameView, HDR_FORMAT, RenderError, RenderPath,
    RendererConfig,
};
use crate::graph::{RenderGraph, TextureAccess, TextureDesc};
use crate::passes::Pass;
use crate::passes::forward::bindings::{FrameGroup, lighting_buffer};
use crate::shader::ShaderProgram;

/// The visibility shading pass: its kernel, its parameters and lighting uniforms.
#[derive(Debug)]
pub struct VisShadePass {
    program: ShaderProgram,
    pipeline: wgpu::ComputePipeline,
    params: wgpu::Buffer,
    lighting: wgpu::Buffer,
}

impl VisShadePass {
    /// The pass for `config`: clustered lists (the path's), refused where the device binds
    /// fewer storage buffers per stage than the kernel reads.
    pub fn new(gpu: &GpuContext, config: &RendererConfig) -> Result<Self, RenderError> {
        let msaa = vis_shade::Msaa::from_value(config.msaa).ok_or_else(|| {
            RenderError::Config(ConfigError::SampleCount {
                asked: config.msaa,
                supported: vis_shade::Msaa::ALL.iter().map(|m| m.value()).collect(),
            })
        })?;
        let variant = vis_shade::variant(vis_shade::VariantKey {
            list: vis_shade::List::List2,
            blend: false,
            scalarize: config.scalarize,
            msaa,
        });
        let storage = variant
            .bindings
            .iter()
            .filter(|b| matches!(b.kind, codegen::rt::BindingKind::Storage { .. }))
            .count() as u32;
        let max = gpu.device().limits().max_storage_buffers_per_shader_stage;
        if storage > max {
            return Err(RenderError::Config(ConfigError::PathNeedsLimit {
                path: RenderPath::Visibility,
                limit: "max_storage_buffers_per_shader_stage",
                needs: storage.into(),
                device: max.into(),
            }));
        }
        let program = gpu.program(variant)?;
        Ok(Self {
            pipeline: program.compute_pipeline(gpu.device(), "shade")?,
            program,
            params: gpu.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some("visibility params"),
                size: size_of::<vis_shade::VisParams>() as u64,
                // COPY_SRC: tools read back what a kernel bound (the tests' host replay).
                usage: wgpu::BufferUsages::UNIFORM
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            lighting: lighting_buffer(gpu.device()),
        })
    }
}

impl VisShadePass {
    /// The kernel's program (a tool records its bindings: `ShaderProgram::record_bindings`).
    #[cfg(any(test, feature = "internals"))]
    pub fn program(&self) -> &ShaderProgram {
        &self.program
    }
}

impl Pass for VisShadePass {
    fn name(&self) -> &'static str {
        "visibility shading"
    }

    /// Refuses a scene whose materials name a material program: the kernel evaluates glTF
    /// PBR's surface for every triangle.
    fn prepare(&mut self, frame: &FrameInputs) -> Result<(), RenderError> {
        match frame.scene.material_program_names().next() {
            Some(program) => Err(crate::materials::MaterialError::NotOnPath {
                program: program.to_string(),
                path: RenderPath::Visibility,
            }
            .into()),
            None => Ok(()),
        }
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let missing = |input| {
            RenderError::Config(ConfigError::MissingInput {
                pass: "visibility shading",
                input,
            })
        };
        let c = &frame.config;
        let vis = resources
            .visibility
            .clone()
            .ok_or(missing("visibility buffer"))?;
        let lists = resources
            .light_lists
            .clone()
            .ok_or(missing("light lists"))?;
        let shadows = resources.shadows.clone().ok_or(missing("shadow atlas"))?;
        let cam = &frame.camera;
        let params = vis_shade::VisParams::new(
            (cam.projection * cam.view).inverse(),
            c.sky,
            vis.draws,
            frame.screen(),
            u32::from(c.view == FrameView::ShadingFrequency),
        );
        frame
            .gpu
            .queue()
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let device = frame.gpu.device();
        let group1 = frame.instances.draw_group_for(device, &self.program)?;
        let group2 = frame.scene.material_group_for(device, &self.program)?;
        let group3 = geometry_group(device, &self.program, &frame.scene, &vis.draw_geometry)?;
        let mut hdr =
            graph.create_texture("hdr", TextureDesc::new_2d(c.width, c.height, HDR_FORMAT));
        let mut pass = graph.add_pass(self.name());
        pass.read_texture(vis.ids, TextureAccess::Sampled)
            .read_texture(shadows.atlas, TextureAccess::Sampled)
            .write_texture(&mut hdr, TextureAccess::StorageWrite);
        crate::frame_data::LightListHandles::read_by(Some(&lists), &mut pass);
        let group = FrameGroup::new(frame, &self.lighting, Some(lists), shadows);
        let (program, pipeline) = (self.program.clone(), self.pipeline.clone());
        let params_buffer = self.params.clone();
        let (ids, (width, height)) = (vis.ids, (c.width, c.height));
        pass.execute(move |ctx| {
            let ids_view = ctx.texture(ids).create_view(&Default::default());
            let out = ctx.texture(hdr).create_view(&Default::default());
            let Some(group0) =
                group.vis_bind_group(ctx, &program, &params_buffer, &ids_view, &out)
            else {
                return;
            };
            let mut pass = ctx
                .encoder
                .begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("visibility shading"),
                    timestamp_writes: None,
                });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &group0, &[]);
            pass.set_bind_group(1, &group1, &[]);
            pass.set_bind_group(2, &group2, &[]);
            pass.set_bind_group(3, &group3, &[]);
            pass.dispatch_workgroups(width.div_ceil(8), height.div_ceil(8), 1);
        });
        resources.hdr = Some(hdr);
        resources.hdr_multisampled = None;
        Ok(())
    }
}
