//! The compute rasteriser and its depth resolve (`shaders_gen`'s `vis_resolve`): with
//! [`crate::frame_data::VisibilityRaster::Compute`], after the visibility raster pass merged the
//! alpha-masked draws into the rasteriser's buffer, a pass of its own (`visibility depth`) draws
//! the resolve full-screen, at sample rate, into a new depth target (loaded: every sample is
//! written, 1.0 where no triangle is), for a pass that reads a depth target (a tool's depth
//! probe, the light heatmap). The frame's own passes read the buffer (the shading, the light
//! culling, the depth pyramid, the blended surfaces and the particles), so the graph leaves the
//! resolve out of their frames.

use std::sync::{Arc, Mutex, PoisonError};

use shaders_gen::visibility::vis_resolve;

use super::ComputeRasterPass;
use super::compute_raster::RasterHalf;
use crate::GpuContext;
use crate::frame_data::{
    DEPTH_FORMAT, FrameInputs, FrameResources, RenderError, RendererConfig, SceneDrawList,
};
use crate::graph::{
    Buffer, BufferAccess, Handle, RenderGraph, Texture, TextureAccess, TextureDesc,
};
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
    /// The resolve's last bind group, kept while the samples' buffer and the frame's width and
    /// sample count stay the same, so a frame that does not resolve (most) neither rebuilds it
    /// nor writes its parameters.
    group: Mutex<Option<ResolveGroup>>,
}

/// The resolve's bind group and what it was built for.
#[derive(Debug)]
struct ResolveGroup {
    vis64: wgpu::Buffer,
    size: (u32, u32),
    group: wgpu::BindGroup,
}

/// The full-screen resolve of a frame's compute-rasteriser samples (`add_depth_resolve`).
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
        let raster = ComputeRasterPass::culled(gpu, config)?;
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
            group: Mutex::default(),
        }))
    }

    /// Adds the compute raster of `half` of `list`'s opaque draws (and their geometry records)
    /// to `graph`; returns the resolve of its samples (the pipeline, its bind group,
    /// and the samples' handle) and the samples' buffer.
    pub(crate) fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
        draws: (&SceneDrawList, &wgpu::Buffer),
        half: RasterHalf,
    ) -> Result<(Resolve, wgpu::Buffer), RenderError> {
        let (vis64, samples) = self
            .raster
            .add_raster(graph, frame, resources, draws, half)?;
        Ok((self.resolve(frame, &vis64, samples)?, vis64))
    }

    /// The resolve of `samples` (in the graph; `vis64` its buffer).
    pub(crate) fn resolve(
        &self,
        frame: &FrameInputs,
        vis64: &wgpu::Buffer,
        samples: Handle<Buffer>,
    ) -> Result<Resolve, RenderError> {
        let c = &frame.config;
        Ok(Resolve {
            pipeline: self.pipeline.clone(),
            group: self.bind_group(&frame.gpu, (c.width, c.msaa), vis64)?,
            samples,
        })
    }

    /// The resolve's bind group over the samples `vis64` of a `width`-pixel-wide frame at
    /// `msaa` samples: the last one where it was built for the same, else a new one after
    /// writing its parameters.
    fn bind_group(
        &self,
        gpu: &GpuContext,
        size: (u32, u32),
        vis64: &wgpu::Buffer,
    ) -> Result<wgpu::BindGroup, RenderError> {
        let mut kept = self.group.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(k) = kept
            .as_ref()
            .filter(|k| k.size == size && &k.vis64 == vis64)
        {
            return Ok(k.group.clone());
        }
        let (width, msaa) = size;
        let params = vis_resolve::ResolveParams::new(width, msaa, glam::UVec2::ZERO);
        gpu.queue()
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let group = vis_resolve::Group0 {
            params: self.params.as_entire_buffer_binding(),
            vis64: vis64.as_entire_buffer_binding(),
        };
        let group = self.program.bind_group(
            gpu.device(),
            vis_resolve::Group0::GROUP,
            &shader_bind::Resources::of(&group),
            "visibility resolve",
        )?;
        *kept = Some(ResolveGroup {
            vis64: vis64.clone(),
            size,
            group: group.clone(),
        });
        Ok(group)
    }
}

/// The load of a depth target under the compute rasteriser: nothing, where no sample's
/// contents before the pass are read. Used by the masked draws' scratch target (stored with
/// `Discard`; their pipelines compare `Always` without writing), by the blended fragments'
/// listing (`passes::forward::over_samples`, the same) and by the depth resolve
/// (which writes every sample). A clear costs what a resolve does (0.6 ms at MSAA 4, 1.2 at
/// MSAA 8 on the H200; BENCHMARKS.md); a load, of a pool texture that an earlier pass of the
/// frame discarded (the graph gives the scratch target and the resolve's target one slot),
/// makes wgpu clear it first.
pub(crate) fn not_loaded() -> wgpu::LoadOp<f32> {
    // SAFETY: `LoadOp::DontCare` leaves the contents undefined until written. Neither user
    // reads them: the masked and listing pipelines neither test nor write depth, and their target is
    // discarded; the resolve writes every sample (a full-screen triangle at sample rate, depth
    // compare `Always`) before anything reads the target.
    wgpu::LoadOp::DontCare(unsafe { wgpu::LoadOpDontCare::enabled() })
}

/// Adds the pass `visibility depth`, which draws `resolve` into a new depth target at the
/// frame's sample count, reading `samples` (the buffer's handle after the masked draws merged
/// into it); returns the target.
pub(crate) fn add_depth_resolve(
    graph: &mut RenderGraph,
    frame: &FrameInputs,
    resolve: Resolve,
    samples: Handle<Buffer>,
) -> Handle<Texture> {
    let c = &frame.config;
    let desc = TextureDesc::new_2d(c.width, c.height, DEPTH_FORMAT).with_samples(c.msaa);
    let mut depth = graph.create_texture("depth", desc);
    graph
        .add_pass("visibility depth")
        .read_buffer(samples, BufferAccess::StorageRead)
        .write_texture(&mut depth, TextureAccess::DepthWrite)
        .execute(move |ctx| {
            let view = ctx.texture(depth).create_view(&Default::default());
            let mut pass = ctx.encoder.begin_render(&wgpu::RenderPassDescriptor {
                label: Some("visibility depth"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &view,
                    depth_ops: Some(wgpu::Operations {
                        // Every sample is written.
                        load: not_loaded(),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&resolve.pipeline);
            pass.set_bind_group(0, &resolve.group, &[]);
            pass.draw(0..3, 0..1);
        });
    depth
}
