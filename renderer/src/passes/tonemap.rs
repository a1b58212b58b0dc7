//! Tonemapping: the resolved HDR colour through exposure and a filmic curve into the caller's
//! target (an sRGB format gets sRGB output).

use shaders_gen::forward::tonemap;

use super::{Pass, draw_fullscreen, fullscreen_pipeline};
use crate::GpuContext;
use crate::frame_data::{FrameInputs, FrameResources, RenderError, RendererConfig};
use crate::graph::{RenderGraph, TextureAccess};
use crate::shader::ShaderProgram;

/// The tonemap pass: its program, pipeline and parameters.
#[derive(Debug)]
pub struct TonemapPass {
    program: ShaderProgram,
    pipeline: wgpu::RenderPipeline,
    params: wgpu::Buffer,
}

impl TonemapPass {
    pub fn new(gpu: &GpuContext, config: &RendererConfig) -> Result<Self, RenderError> {
        let key = tonemap::VariantKey {
            curve: tonemap::Curve::Curve0,
        };
        let program = ShaderProgram::new(&gpu.device, gpu.capabilities(), tonemap::variant(key))?;
        Ok(Self {
            pipeline: fullscreen_pipeline(
                &gpu.device,
                &program,
                "fs_tonemap",
                config.output_format,
            ),
            program,
            params: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("tonemap"),
                size: size_of::<tonemap::TonemapParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        })
    }
}

impl Pass for TonemapPass {
    fn name(&self) -> &'static str {
        "tonemap"
    }

    fn prepare(&mut self, frame: &FrameInputs) -> Result<(), RenderError> {
        let params = tonemap::TonemapParams::new(frame.config.exposure);
        frame
            .gpu
            .queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        Ok(())
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        _frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let hdr = resources.hdr.ok_or(RenderError::MissingInput {
            pass: "tonemap",
            input: "HDR colour",
        })?;
        let target = resources.output;
        let layout = self.program.bind_group_layouts[0].clone();
        let (pipeline, params) = (self.pipeline.clone(), self.params.clone());
        graph
            .add_pass(self.name())
            .read_texture(hdr, TextureAccess::Sampled)
            .write_texture(&mut resources.output, TextureAccess::ColorAttachment)
            .execute(move |ctx| {
                let hdr_view = ctx.texture(hdr).create_view(&Default::default());
                let out_view = ctx.texture(target).create_view(&Default::default());
                let bound = [
                    params.as_entire_binding(),
                    wgpu::BindingResource::TextureView(&hdr_view),
                ];
                draw_fullscreen(ctx, "tonemap", (&layout, &pipeline), &bound, &out_view);
            });
        Ok(())
    }
}
