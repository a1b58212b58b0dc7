//! The shadow-atlas debug view ([`crate::frame_data::FrameView::ShadowAtlas`]): the atlas
//! drawn into the output, letterboxed, depth as grey, each region outlined in its light's
//! colour. Tools label the regions from [`crate::shadow::ShadowReport::regions`].

use crate::frame_data::ConfigError;
use shaders_gen::shadow::shadow_atlas_view;
use wgpu::util::DeviceExt as _;

use super::super::{Pass, draw_fullscreen, fullscreen_pipeline};
use crate::GpuContext;
use crate::frame_data::{FrameInputs, FrameResources, RenderError, RendererConfig};
use crate::graph::{RenderGraph, TextureAccess};
use crate::shader::ShaderProgram;

/// The atlas view pass.
#[derive(Debug)]
pub struct ShadowAtlasViewPass {
    program: ShaderProgram,
    pipeline: wgpu::RenderPipeline,
    params: wgpu::Buffer,
}

impl ShadowAtlasViewPass {
    pub fn new(gpu: &GpuContext, config: &RendererConfig) -> Result<Self, RenderError> {
        let program = gpu.program(&shadow_atlas_view::VARIANTS[0])?;
        Ok(Self {
            pipeline: fullscreen_pipeline(gpu.device(), &program, "fs_atlas", config.output_format),
            program,
            params: gpu.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some("shadow atlas view"),
                size: size_of::<shadow_atlas_view::AtlasViewParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        })
    }
}

impl Pass for ShadowAtlasViewPass {
    fn name(&self) -> &'static str {
        "shadow atlas view"
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let shadows =
            resources
                .shadows
                .clone()
                .ok_or(RenderError::Config(ConfigError::MissingInput {
                    pass: "shadow atlas view",
                    input: "shadow atlas",
                }))?;
        let mut regions: Vec<[u32; 4]> = shadows.regions.to_vec();
        let count = regions.len() as u32;
        if regions.is_empty() {
            regions.push([0; 4]);
        }
        let params = shadow_atlas_view::AtlasViewParams::new(
            frame.screen(),
            shadows.atlas_view.texture().width(),
            count,
        );
        let queue = frame.gpu.queue();
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let region_buffer =
            frame
                .gpu
                .device()
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("shadow atlas view regions"),
                    contents: bytemuck::cast_slice(&regions),
                    usage: wgpu::BufferUsages::STORAGE,
                });
        let (target, output_format) = (resources.output, frame.config.output_format);
        let program = self.program.clone();
        let (pipeline, params) = (self.pipeline.clone(), self.params.clone());
        graph
            .add_pass(self.name())
            .read_texture(shadows.atlas, TextureAccess::Sampled)
            .write_texture(&mut resources.output, TextureAccess::ColorAttachment)
            .execute(move |ctx| {
                let out_view = crate::frame_data::output_view(ctx.texture(target), output_format);
                let label = "shadow atlas view";
                let group = shadow_atlas_view::Group0 {
                    params: params.as_entire_buffer_binding(),
                    atlas: &shadows.atlas_view,
                    regions: region_buffer.as_entire_buffer_binding(),
                }
                .bind_group(ctx.device, program.layout(0), program.variant, label);
                draw_fullscreen(ctx, label, &pipeline, group, &out_view);
            });
        Ok(())
    }
}
