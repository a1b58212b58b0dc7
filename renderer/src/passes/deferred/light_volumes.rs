//! Traditional deferred shading's lighting pass (`RenderPath::Deferred`): every punctual
//! light drawn as a light volume, the back faces of the cube around its bounding sphere
//! (`tbdr::vs_light_volume`), shaded from the G-buffer by `tbdr::fs_light_volume` and blended
//! additively into the resolved image the deferred base pass wrote. There is no culling: a
//! light costs the pixels its volume covers, which is what reference 000 measures this method
//! for.
//!
//! The target is the single-sample resolved image, so the multisampled depth cannot be
//! attached: the fragment reads the depth from the G-buffer and discards the pixels the light
//! does not reach. Edge pixels (the base pass's bits) are shaded per sample.

use crate::frame_data::ConfigError;
use shaders_gen::deferred::light_volume;
use shaders_gen::shared::light_spheres;

use super::tiled_shading::{GBufferViews, kernel_params, read_gbuffer, upload_spheres};
use crate::GpuContext;
use crate::frame_data::{FrameInputs, FrameResources, HDR_FORMAT, RenderError, RendererConfig};
use crate::graph::{RenderGraph, TextureAccess};
use crate::passes::{Pass, color_pass};
use crate::shader::ShaderProgram;

/// Vertices of one light volume: the cube's twelve triangles.
const CUBE_VERTICES: u32 = 36;

/// The light-volume pass.
#[derive(Debug)]
pub struct LightVolumePass {
    gpu: GpuContext,
    program: ShaderProgram,
    pipeline: wgpu::RenderPipeline,
    params: wgpu::Buffer,
    spheres: wgpu::Buffer,
}

impl LightVolumePass {
    pub fn new(gpu: &GpuContext, config: &RendererConfig) -> Result<Self, RenderError> {
        let msaa = light_volume::Msaa::from_value(config.msaa).ok_or_else(|| {
            RenderError::Config(ConfigError::SampleCount {
                asked: config.msaa,
                supported: light_volume::Msaa::ALL.iter().map(|m| m.value()).collect(),
            })
        })?;
        let variant = light_volume::variant(light_volume::VariantKey { msaa });
        let program = gpu.program(variant)?;
        let pipeline = volume_pipeline(gpu.device(), &program);
        let buffer = |label, size, usage| {
            gpu.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        Ok(Self {
            gpu: gpu.clone(),
            program,
            pipeline,
            params: buffer(
                "light volume params",
                size_of::<light_volume::TbdrParams>() as u64,
                wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            ),
            spheres: buffer(
                "light volume spheres",
                16,
                wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            ),
        })
    }
}

/// Back faces only (the front faces are culled), no depth test, additive blending into one
/// single-sample HDR target.
fn volume_pipeline(device: &wgpu::Device, program: &ShaderProgram) -> wgpu::RenderPipeline {
    let add = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    };
    program.render_pipeline(
        device,
        &wgpu::RenderPipelineDescriptor {
            label: Some("light volumes"),
            layout: Some(&program.pipeline_layout),
            vertex: wgpu::VertexState {
                module: &program.module,
                entry_point: Some("vs_light_volume"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState {
                front_face: wgpu::FrontFace::Ccw,
                cull_mode: Some(wgpu::Face::Front),
                ..Default::default()
            },
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &program.module,
                entry_point: Some("fs_light_volume"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: HDR_FORMAT,
                    blend: Some(wgpu::BlendState {
                        color: add,
                        alpha: add,
                    }),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        },
    )
}

impl Pass for LightVolumePass {
    fn name(&self) -> &'static str {
        "light volumes"
    }

    fn prepare(&mut self, frame: &FrameInputs) -> Result<(), RenderError> {
        upload_spheres(&self.gpu, &mut self.spheres, frame);
        let params = kernel_params(frame, frame.lights.punctual.len() as u32, false);
        self.gpu
            .queue()
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        Ok(())
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let missing = |input| {
            RenderError::Config(ConfigError::MissingInput {
                pass: "light volumes",
                input,
            })
        };
        let depth = resources.depth.ok_or(missing("pre-Z depth"))?;
        let gbuffer = resources.gbuffer.ok_or(missing("G-buffer"))?;
        let shadows = resources.shadows.clone().ok_or(missing("shadow atlas"))?;
        let mut hdr = resources.hdr.ok_or(missing("deferred base image"))?;
        let edges = resources
            .deferred_edges
            .clone()
            .ok_or(missing("deferred base edge bits"))?;
        let mut pass = graph.add_pass(self.name());
        read_gbuffer(&mut pass, depth, gbuffer, &shadows)
            .write_texture(&mut hdr, TextureAccess::ColorAttachment);
        let program = self.program.clone();
        let pipeline = self.pipeline.clone();
        let (params, spheres) = (self.params.clone(), self.spheres.clone());
        let lights = std::sync::Arc::clone(&frame.lights);
        let count = frame.lights.punctual.len() as u32;
        pass.execute(move |ctx| {
            let views = GBufferViews::new(ctx, depth, gbuffer);
            let group = light_volume::Group0 {
                edge_bits: edges.as_entire_buffer_binding(),
                tbdr_gbuffer: views.bindings(&params),
                light_set: lights.bindings(),
                light_spheres: light_spheres::Group0 {
                    spheres: spheres.as_entire_buffer_binding(),
                },
                shadow_atlas: shadows.bindings(),
            }
            .bind_group(
                ctx.device,
                program.layout(light_volume::Group0::GROUP),
                program.variant,
                "light volumes",
            );
            let Some(group) = ctx.bind(group) else {
                return;
            };
            let target = ctx.texture(hdr).create_view(&Default::default());
            let load = wgpu::LoadOp::Load;
            let mut pass = color_pass(&mut ctx.encoder, "light volumes", &target, load);
            if count > 0 {
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, &group, &[]);
                pass.draw(0..CUBE_VERTICES, 0..count);
            }
        });
        resources.hdr = Some(hdr);
        Ok(())
    }
}
