//! The compute rasteriser and its depth resolve (`shaders_gen`'s `vis_resolve`): with
//! [`crate::frame_data::VisibilityRaster::Compute`] the visibility raster pass draws the resolve
//! full-screen, at sample rate, into its depth target (loaded: every sample is written, 1.0
//! where no triangle is) before the alpha-masked draws, for the passes after it that
//! depth-test in hardware. The IDs stay in the compute rasteriser's buffer, which the shading,
//! the light culling and the depth pyramid read.

use std::sync::Arc;

use shaders_gen::visibility::vis_resolve;

use super::ComputeRasterPass;
use crate::GpuContext;
use crate::frame_data::{FrameInputs, FrameResources, RenderError, RendererConfig, SceneDrawList};
use crate::graph::{Buffer, Handle, RenderGraph};
use crate::passes::depth_state;
use crate::shader::ShaderProgram;

/// The compute rasteriser and the resolve of its samples, shared by both halves of the
/// visibility raster pass.
#[derive(Debug)]
pub(crate) struct ComputeStage {
    raster: ComputeRasterPass,
    program: ShaderProgram,
    pipeline: wgpu::RenderPipeline,
    params: wgpu::Buffer,
}

/// What the visibility pass draws first under the compute raster: the full-screen resolve.
pub(crate) struct Resolve {
    pub(crate) pipeline: wgpu::RenderPipeline,
    pub(crate) group: wgpu::BindGroup,
    /// The compute raster's samples, which the resolve reads.
    pub(crate) samples: Handle<Buffer>,
}

impl ComputeStage {
    /// The stage for `config`; refused on a device without 64-bit atomic min/max (the compute
    /// rasteriser's variant error).
    pub(crate) fn new(gpu: &GpuContext, config: &RendererConfig) -> Result<Arc<Self>, RenderError> {
        let raster = ComputeRasterPass::new(gpu, config)?;
        let program = gpu.program(vis_resolve::variant(vis_resolve::VariantKey {}))?;
        let pipeline = program.render_pipeline(
            gpu.device(),
            &wgpu::RenderPipelineDescriptor {
                label: Some("visibility resolve"),
                layout: Some(&program.pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &program.module,
                    entry_point: Some("vs_fullscreen"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
                // Every sample takes the depth the buffer holds, 1.0 where no triangle is.
                depth_stencil: Some(depth_state(true, wgpu::CompareFunction::Always)),
                multisample: wgpu::MultisampleState {
                    count: config.msaa,
                    ..Default::default()
                },
                fragment: Some(wgpu::FragmentState {
                    module: &program.module,
                    entry_point: Some("fs_resolve"),
                    compilation_options: Default::default(),
                    targets: &[],
                }),
                multiview_mask: None,
                cache: None,
            },
        );
        let params = gpu.device().create_buffer(&wgpu::BufferDescriptor {
            label: Some("visibility resolve params"),
            size: size_of::<vis_resolve::ResolveParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Ok(Arc::new(Self {
            raster,
            program,
            pipeline,
            params,
        }))
    }

    /// Adds the compute raster of `list`'s opaque draws (their geometry records and count) to
    /// `graph`; returns what the visibility pass needs to resolve its samples: the pipeline,
    /// its bind group, and the samples' handle to read.
    pub(crate) fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
        draws: (&SceneDrawList, &wgpu::Buffer, u32),
    ) -> Result<(Resolve, wgpu::Buffer), RenderError> {
        let (vis64, samples) = self.raster.add_raster(graph, frame, resources, draws)?;
        let c = &frame.config;
        let resolve = Resolve {
            pipeline: self.pipeline.clone(),
            group: self.bind_group(&frame.gpu, (c.width, c.msaa), &vis64)?,
            samples,
        };
        Ok((resolve, vis64))
    }

    /// The compute rasteriser's buffer of this frame (after `add_to_graph`).
    pub(crate) fn samples_buffer(&self) -> Option<wgpu::Buffer> {
        self.raster.samples_buffer()
    }

    /// The resolve's bind group over the samples `vis64` of a `width`-pixel-wide frame at
    /// `msaa` samples, after writing its parameters.
    fn bind_group(
        &self,
        gpu: &GpuContext,
        (width, msaa): (u32, u32),
        vis64: &wgpu::Buffer,
    ) -> Result<wgpu::BindGroup, RenderError> {
        let params = vis_resolve::ResolveParams::new(width, msaa, glam::UVec2::ZERO);
        gpu.queue()
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let group = vis_resolve::Group0 {
            params: self.params.as_entire_buffer_binding(),
            vis64: vis64.as_entire_buffer_binding(),
        };
        Ok(self.program.bind_group(
            gpu.device(),
            vis_resolve::Group0::GROUP,
            &shader_bind::Resources::of(&group),
            "visibility resolve",
        )?)
    }
}
