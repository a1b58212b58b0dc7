//! Depth pre-pass: every opaque and masked draw into the MSAA depth buffer, so culling sees the
//! scene's depth and forward shading runs once per visible sample. Masked materials discard
//! texels below their cutoff here too, so they leave no depth where they are see-through.
//!
//! With occlusion culling it runs twice: first the draws visible last frame, into a cleared
//! depth buffer; then ([`PrezPass::late`], after `passes::scene_cull::occlusion`) the draws the
//! occlusion test found visible that the first half left out, over that depth.

use crate::frame_data::ConfigError;
use shaders_gen::forward::prez;

use super::{
    FacePipelines, MeshPipeline, Pass, SceneDraws, depth_state, face_pipeline, face_pipelines,
    mesh_pipeline,
};
use crate::GpuContext;
use crate::frame_data::{DEPTH_FORMAT, FrameInputs, FrameResources, RenderError, RendererConfig};
use crate::graph::{BufferAccess, RenderGraph, TextureAccess, TextureDesc};
use crate::scene::VertexStreams;
use crate::shader::ShaderProgram;

/// The pre-Z pass: its programs and pipelines (`[double_sided][mirrored]`, plain and
/// alpha-masked).
#[derive(Debug)]
pub struct PrezPass {
    program: ShaderProgram,
    plain: FacePipelines,
    masked: FacePipelines,
    /// Group 0 over the renderer's camera uniform (the buffer lives as long as the renderer).
    camera_group: Option<wgpu::BindGroup>,
    /// The second half (occlusion culling's late draws, over the first half's depth).
    late: bool,
}

impl PrezPass {
    pub fn new(gpu: &GpuContext, config: &RendererConfig) -> Result<Self, RenderError> {
        let program = gpu.program(prez::variant(prez::VariantKey { alpha_mask: false }))?;
        let mask_program = gpu.program(prez::variant(prez::VariantKey { alpha_mask: true }))?;
        let pipelines = |program: &ShaderProgram, masked: bool| {
            face_pipelines(|d, m| pipeline(gpu.device(), program, config.msaa, masked, d, m))
        };
        Ok(Self {
            plain: pipelines(&program, false),
            masked: pipelines(&mask_program, true),
            program,
            camera_group: None,
            late: false,
        })
    }

    /// The second half of pre-Z under occlusion culling: the draws its test found visible that
    /// the first half did not draw, over the first half's depth, with the first half's
    /// programs and pipelines. It adds nothing to a frame without occlusion culling.
    pub fn late(&self) -> Self {
        Self {
            program: self.program.clone(),
            plain: self.plain.clone(),
            masked: self.masked.clone(),
            camera_group: None,
            late: true,
        }
    }
}

fn pipeline(
    device: &wgpu::Device,
    program: &ShaderProgram,
    msaa: u32,
    masked: bool,
    double_sided: bool,
    mirrored: bool,
) -> wgpu::RenderPipeline {
    mesh_pipeline(
        device,
        program,
        &MeshPipeline {
            label: if masked { "pre-z masked" } else { "pre-z" },
            vertex_entry: if masked { "vs_prez_mask" } else { "vs_prez" },
            // Opaque draws read positions only; masked ones the UV sets and vertex colour too.
            streams: if masked {
                &super::MASK_STREAMS
            } else {
                &[wgpu::VertexFormat::Float32x3]
            },
            double_sided,
            mirrored,
            depth: Some(depth_state(true, wgpu::CompareFunction::Less)),
            msaa,
            // Opaque draws need no fragment stage at all; masked ones discard.
            fragment: masked.then_some(("fs_prez_mask", &[][..])),
        },
    )
}

impl Pass for PrezPass {
    fn name(&self) -> &'static str {
        if self.late { "pre-z (late)" } else { "pre-z" }
    }

    fn prepare(&mut self, frame: &FrameInputs) -> Result<(), RenderError> {
        if self.camera_group.is_none() {
            let group = prez::Group0 {
                camera: frame.camera_uniform.buffer.as_entire_buffer_binding(),
            }
            .bind_group(
                frame.gpu.device(),
                self.program.layout(0),
                self.program.variant,
                "pre-z camera",
            )?;
            self.camera_group = Some(group);
        }
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
                pass: "pre-z",
                input,
            })
        };
        let mut list = resources
            .scene_draws
            .clone()
            .ok_or(missing("the scene's draw batches (scene culling)"))?;
        let (mut depth, load) = if self.late {
            // The second half draws occlusion culling's late slots over the first's depth.
            let Some(late) = list.late_half() else {
                return Ok(());
            };
            list = late;
            let depth = resources.depth.ok_or(missing("the first half's depth"))?;
            (depth, wgpu::LoadOp::Load)
        } else {
            let c = &frame.config;
            let desc = TextureDesc::new_2d(c.width, c.height, DEPTH_FORMAT).with_samples(c.msaa);
            (
                graph.create_texture("depth", desc),
                wgpu::LoadOp::Clear(1.0),
            )
        };
        let target = depth;
        let camera_group = self
            .camera_group
            .clone()
            .ok_or(missing("camera bind group (built in prepare)"))?;
        let (plain, masked) = (self.plain.clone(), self.masked.clone());
        let scene = std::sync::Arc::clone(&frame.scene);
        let instances = std::sync::Arc::clone(&frame.instances);
        graph
            .add_pass(self.name())
            .read_buffer(list.args, BufferAccess::Indirect)
            .write_texture(&mut depth, TextureAccess::DepthWrite)
            .execute(move |ctx| {
                let view = ctx.texture(target).create_view(&Default::default());
                let mut pass = ctx.encoder.begin_render(&wgpu::RenderPassDescriptor {
                    label: Some("pre-z"),
                    color_attachments: &[],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &view,
                        depth_ops: Some(wgpu::Operations {
                            load,
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_bind_group(0, &camera_group, &[]);
                // Opaque draws read only slot 0 of the masked streams. Blended surfaces are in
                // no batch: they must not hide what is behind them.
                let mut draws = SceneDraws::new(&mut pass, &scene, &instances, VertexStreams::Mask);
                draws.draw_batches(&list, &instances, |batch| {
                    let pipelines = if batch.masked { &masked } else { &plain };
                    let pipeline = face_pipeline(pipelines, batch.double_sided, batch.mirrored);
                    (pipeline, batch.masked.then(|| scene.mask_group()))
                });
            });
        resources.depth = Some(depth);
        Ok(())
    }
}
