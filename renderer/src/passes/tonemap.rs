//! Tonemapping: the resolved HDR colour through exposure and a filmic curve into the caller's
//! target (an sRGB format gets sRGB output).

use crate::frame_data::ConfigError;
use shaders_gen::forward::tonemap;

use super::{Pass, draw_fullscreen, fullscreen_pipeline};
use crate::GpuContext;
use crate::frame_data::{FrameInputs, FrameResources, FrameView, RenderError, RendererConfig};
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
        let program = gpu.program(tonemap::variant(key))?;
        Ok(Self {
            pipeline: fullscreen_pipeline(
                gpu.device(),
                &program,
                "fs_tonemap",
                config.output_format,
            ),
            program,
            params: gpu.device().create_buffer(&wgpu::BufferDescriptor {
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

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let c = &frame.config;
        // The particle-atlas view shows the lit atlas, fitted to the target's shorter side.
        let atlas = resources
            .particles
            .as_ref()
            .filter(|_| c.view == FrameView::ParticleAtlas)
            .and_then(|p| p.lit_atlas.map(|a| (a, p.atlas_side)));
        let (source, scale) = match atlas {
            Some((a, side)) => (Some(a), side as f32 / c.width.min(c.height) as f32),
            None => (resources.hdr, 1.0),
        };
        let hdr = source.ok_or(RenderError::Config(ConfigError::MissingInput {
            pass: "tonemap",
            input: if c.view == FrameView::ParticleAtlas {
                "particle lighting atlas (the frame has no particles)"
            } else {
                "HDR colour"
            },
        }))?;
        let params = tonemap::TonemapParams::new(c.exposure, scale);
        frame
            .gpu
            .queue()
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let target = resources.output;
        let program = self.program.clone();
        let (pipeline, params) = (self.pipeline.clone(), self.params.clone());
        graph
            .add_pass(self.name())
            .read_texture(hdr, TextureAccess::Sampled)
            .write_texture(&mut resources.output, TextureAccess::ColorAttachment)
            .execute(move |ctx| {
                let hdr_view = ctx.texture(hdr).create_view(&Default::default());
                let out_view = ctx.texture(target).create_view(&Default::default());
                let group = tonemap::Group0 {
                    params: params.as_entire_buffer_binding(),
                    hdr: &hdr_view,
                }
                .bind_group(
                    ctx.device,
                    program.layout(0),
                    program.variant,
                    "tonemap",
                );
                draw_fullscreen(ctx, "tonemap", &pipeline, group, &out_view);
            });
        Ok(())
    }
}
