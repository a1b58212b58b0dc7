//! The visibility raster pass: every opaque and alpha-masked draw of the scene's batches into
//! the multisampled depth buffer and the visibility buffer (`shaders_gen`'s `vis_raster`). With
//! [`VisibilityRaster::Compute`] the compute rasteriser draws the opaque ones first
//! (`super::compute_raster`) into its buffer, which is then the frame's visibility samples
//! ([`VisibilitySamples::Buffer`]): this pass adds the alpha-masked draws to it with the same
//! 64-bit atomics (`vis_raster`'s `vis64` variant), and resolves its depths into the depth
//! target first (`super::resolve`) for the passes that depth-test in hardware. Without masked
//! draws it writes only that target, and the graph leaves it out of a frame that reads none;
//! with masked draws it always runs (they write the buffer) and resolves the depth too.
//!
//! The depth is cleared and the ID target only loaded: a sample at depth 1.0 is sky whatever
//! ID it holds, and every reader of the IDs tests the depth first (`vis_frame::vis_id_at`).

use std::sync::{Arc, Mutex, PoisonError};

use shaders_gen::visibility::vis_raster;

use super::geometry::{
    SceneState, draw_geometry, draw_geometry_buffer, geometry_group, sequence_buffer,
};
use super::resolve::{ComputeStage, Resolve};
use crate::GpuContext;
use crate::frame_data::{
    ConfigError, DEPTH_FORMAT, FrameInputs, FrameResources, InstanceTable, RenderError,
    RendererConfig, VISIBILITY_FORMAT, VisibilityHandles, VisibilityRaster, VisibilitySamples,
};
use crate::graph::{
    BufferAccess, Handle, PassBuilder, PassContext, RenderGraph, Texture, TextureAccess,
    TextureDesc,
};
use crate::passes::{
    BatchState, FacePipelines, MeshPipeline, Pass, SceneDraws, depth_state, face_pipeline,
    face_pipelines, mesh_pipeline,
};
use crate::scene::VertexStreams;
use crate::shader::ShaderProgram;

/// The visibility raster pass: its programs and pipelines (`[double_sided][mirrored]`, plain
/// and alpha-masked). With occlusion culling it runs twice, as pre-Z does: first the draws
/// visible last frame into cleared depth (the IDs are loaded; under the compute rasteriser,
/// the resolved depth and its buffer); then ([`VisRasterPass::late`], after
/// `passes::scene_cull::occlusion`) the draws the occlusion test found visible that the first
/// half left out, over them.
#[derive(Debug)]
pub struct VisRasterPass {
    program: ShaderProgram,
    mask_program: ShaderProgram,
    plain: FacePipelines,
    masked: FacePipelines,
    /// Shared by both halves.
    state: Arc<Mutex<SceneState>>,
    /// The second half (occlusion culling's late draws).
    late: bool,
    /// With [`VisibilityRaster::Compute`]: the compute rasteriser and its resolve.
    compute: Option<Arc<ComputeStage>>,
    /// With [`VisibilityRaster::Compute`]: the masked program's `SAMPLES` uniform.
    sample_layout: Option<wgpu::Buffer>,
}

impl VisRasterPass {
    /// The pass for `config`, refused when the device cannot multisample the visibility
    /// buffer at `config.msaa`, or (with [`VisibilityRaster::Compute`]) has no 64-bit atomic
    /// min/max.
    pub fn new(gpu: &GpuContext, config: &RendererConfig) -> Result<Self, RenderError> {
        let supported = gpu.capabilities().msaa_r32uint.clone();
        if !supported.contains(&config.msaa) {
            return Err(RenderError::Config(ConfigError::SampleCount {
                asked: config.msaa,
                supported,
            }));
        }
        let compute = match config.visibility_raster {
            VisibilityRaster::Hardware => None,
            VisibilityRaster::Compute => Some(ComputeStage::new(gpu, config)?),
        };
        // Under the compute rasteriser the masked draws add their samples to its buffer.
        let vis64 = compute.is_some();
        let program = |alpha_mask, vis64| {
            let variant = vis_raster::variant(vis_raster::VariantKey { alpha_mask, vis64 })?;
            Ok::<_, RenderError>(gpu.program(variant)?)
        };
        let (program, mask_program) = (program(false, false)?, program(true, vis64)?);
        let ids_target = [Some(wgpu::ColorTargetState {
            format: VISIBILITY_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let pipelines = |program: &ShaderProgram, masked: bool| {
            let fragment = if masked && vis64 {
                ("fs_vis64", &[][..])
            } else {
                ("fs_vis", &ids_target[..])
            };
            face_pipelines(|double_sided, mirrored| {
                mesh_pipeline(
                    gpu.device(),
                    program,
                    &MeshPipeline {
                        label: if masked {
                            "visibility masked"
                        } else {
                            "visibility"
                        },
                        vertex_entry: "vs_vis",
                        // Vertices are pulled from storage.
                        streams: &[],
                        double_sided,
                        mirrored,
                        depth: depth_state(true, wgpu::CompareFunction::Less),
                        msaa: config.msaa,
                        fragment: Some(fragment),
                    },
                )
            })
        };
        Ok(Self {
            plain: pipelines(&program, false),
            masked: pipelines(&mask_program, true),
            program,
            mask_program,
            state: Arc::default(),
            late: false,
            sample_layout: vis64.then(|| {
                gpu.device().create_buffer(&wgpu::BufferDescriptor {
                    label: Some("visibility sample layout"),
                    size: size_of::<vis_raster::SampleLayout>() as u64,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            }),
            compute,
        })
    }

    /// The second half under occlusion culling: the draws its test found visible that the
    /// first half left out, over the first half's depth and IDs, with the same programs,
    /// pipelines and geometry records. It adds nothing to a frame without occlusion culling.
    pub fn late(&self) -> Self {
        Self {
            program: self.program.clone(),
            mask_program: self.mask_program.clone(),
            plain: self.plain.clone(),
            masked: self.masked.clone(),
            state: Arc::clone(&self.state),
            late: true,
            compute: self.compute.clone(),
            sample_layout: self.sample_layout.clone(),
        }
    }
}

impl VisRasterPass {
    /// Group 0 (the camera; for the masked program under the compute rasteriser, its buffer
    /// `vis64` too) and group 3 of the plain and the masked programs: `(camera, mask camera,
    /// geometry, mask geometry)`.
    fn groups(
        &self,
        frame: &FrameInputs,
        draw_geometry: &wgpu::Buffer,
        vis64: Option<&wgpu::Buffer>,
    ) -> Result<[wgpu::BindGroup; 4], RenderError> {
        let device = frame.gpu.device();
        let geometry = geometry_group(device, &self.program, &frame.scene, draw_geometry)?;
        let mask_geometry =
            geometry_group(device, &self.mask_program, &frame.scene, draw_geometry)?;
        let camera = frame.camera_uniform.buffer.as_entire_buffer_binding();
        let layout = match (vis64, &self.sample_layout) {
            (Some(_), Some(layout)) => {
                let c = &frame.config;
                let params = vis_raster::SampleLayout::new(c.width, c.msaa, glam::UVec2::ZERO);
                frame
                    .gpu
                    .queue()
                    .write_buffer(layout, 0, bytemuck::bytes_of(&params));
                Some(layout.as_entire_buffer_binding())
            }
            _ => None,
        };
        let group0 = |program: &ShaderProgram, group: vis_raster::Group0<'_>| {
            program.bind_group(
                device,
                vis_raster::Group0::GROUP,
                &shader_bind::Resources::of(&group),
                "visibility camera",
            )
        };
        let plain = vis_raster::Group0 {
            camera: camera.clone(),
            vis64: None,
            samples: None,
        };
        let masked = vis_raster::Group0 {
            camera,
            vis64: vis64.map(wgpu::Buffer::as_entire_buffer_binding),
            samples: layout,
        };
        Ok([
            group0(&self.program, plain)?,
            group0(&self.mask_program, masked)?,
            geometry,
            mask_geometry,
        ])
    }
}

impl VisRasterPass {
    /// The draws' geometry records, how many, and the sequence index buffer (built in
    /// `prepare`).
    fn kept_buffers(&self) -> Option<(wgpu::Buffer, u32, wgpu::Buffer)> {
        let state = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        let (sequence, _) = state.sequence.clone()?;
        Some((
            state.draw_geometry.clone()?,
            state.records.len() as u32,
            sequence,
        ))
    }
}

impl Pass for VisRasterPass {
    fn name(&self) -> &'static str {
        if self.late {
            "visibility (late)"
        } else {
            "visibility"
        }
    }

    fn prepare(&mut self, frame: &FrameInputs) -> Result<(), RenderError> {
        let device = frame.gpu.device();
        let mut state = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        let key = (
            frame.scene.id,
            frame.instances.id(),
            frame.instances.revision,
        );
        if state.key != Some(key) {
            if !state.still_valid(frame.scene.id, &frame.instances) {
                let records = draw_geometry(&frame.instances);
                state.draw_geometry = Some(draw_geometry_buffer(device, &records));
                state.records = records;
            }
            state.key = Some(key);
        }
        let indices = frame.scene.gpu.geometry.indices.size() / 4;
        if state.sequence.as_ref().is_none_or(|(_, n)| *n < indices) {
            let count = u32::try_from(indices).unwrap_or(u32::MAX);
            state.sequence = Some((sequence_buffer(device, count), indices));
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
                pass: "visibility",
                input,
            })
        };
        let mut list = resources
            .scene_draws
            .clone()
            .ok_or(missing("the scene's draw batches (scene culling)"))?;
        let first = if self.late {
            // The second half draws occlusion culling's late slots over the first's output.
            let Some(late) = list.late_half() else {
                return Ok(());
            };
            list = late;
            let depth = resources.depth.ok_or(missing("the first half's depth"))?;
            let vis = resources
                .visibility
                .clone()
                .ok_or(missing("the first half's visibility buffer"))?;
            Some((depth, vis.samples))
        } else {
            None
        };
        let (draw_geometry, draws, sequence) = self.kept_buffers().ok_or(missing(
            "draw geometry and sequence indices (built in prepare)",
        ))?;
        // Under the compute rasteriser its buffer holds the IDs: the first half rasterises
        // the opaque draws into it and resolves their depths; both halves add the masked
        // draws' samples to it.
        let (resolve, vis64) = match (&self.compute, first) {
            (Some(stage), None) => {
                let (resolve, buffer) =
                    stage.add_to_graph(graph, frame, resources, (&list, &draw_geometry, draws))?;
                (Some(resolve), Some(buffer))
            }
            (Some(stage), Some(_)) => (None, stage.samples_buffer()),
            (None, _) => (None, None),
        };
        let [camera, mask_camera, geometry, mask_geometry] =
            self.groups(frame, &draw_geometry, vis64.as_ref())?;
        let (mut depth, mut samples) = match first {
            Some(kept) => kept,
            None => new_targets(graph, frame, resolve.as_ref()),
        };
        let recording = Recording {
            plain: self.plain.clone(),
            masked: self.masked.clone(),
            scene: Arc::clone(&frame.scene),
            instances: Arc::clone(&frame.instances),
            camera,
            mask_camera,
            geometry,
            mask_geometry,
            sequence,
            list: list.clone(),
            depth,
            ids: match samples {
                VisibilitySamples::Targets { ids } => Some(ids),
                VisibilitySamples::Buffer { .. } => None,
            },
            load: first.is_some(),
            masked_only: self.compute.is_some(),
            resolve,
        };
        let mut pass = graph.add_pass(self.name());
        pass.read_buffer(list.args, BufferAccess::Indirect)
            .write_texture(&mut depth, TextureAccess::DepthWrite);
        let masked = list.layout.batches.iter().any(|b| b.masked);
        declare_samples(&mut pass, &mut samples, masked);
        pass.execute(move |ctx| recording.record(ctx));
        resources.depth = Some(depth);
        resources.visibility = Some(VisibilityHandles {
            samples,
            draw_geometry,
            draws,
        });
        Ok(())
    }
}

/// The first half's depth target and visibility samples: the compute rasteriser's buffer
/// where it ran (`resolve`), else a new ID target.
fn new_targets(
    graph: &mut RenderGraph,
    frame: &FrameInputs,
    resolve: Option<&Resolve>,
) -> (Handle<Texture>, VisibilitySamples) {
    let c = &frame.config;
    let size = TextureDesc::new_2d(c.width, c.height, DEPTH_FORMAT).with_samples(c.msaa);
    let samples = match resolve {
        Some(r) => VisibilitySamples::Buffer { samples: r.samples },
        None => {
            let ids =
                TextureDesc::new_2d(c.width, c.height, VISIBILITY_FORMAT).with_samples(c.msaa);
            VisibilitySamples::Targets {
                ids: graph.create_texture("visibility", ids),
            }
        }
    };
    (graph.create_texture("depth", size), samples)
}

/// Declares what the pass does with the samples: writes the ID target, or adds the `masked`
/// draws to the compute rasteriser's buffer. Without masked draws the pass only resolves the
/// depth, and the graph leaves it out of a frame that reads no depth target.
fn declare_samples(pass: &mut PassBuilder<'_>, samples: &mut VisibilitySamples, masked: bool) {
    match samples {
        VisibilitySamples::Targets { ids } => {
            pass.write_texture(ids, TextureAccess::ColorAttachment);
        }
        VisibilitySamples::Buffer { samples } if masked => {
            pass.write_buffer(samples, BufferAccess::StorageWrite);
        }
        VisibilitySamples::Buffer { samples } => {
            pass.read_buffer(*samples, BufferAccess::StorageRead);
        }
    }
}

/// What one frame's visibility pass records with.
struct Recording {
    plain: FacePipelines,
    masked: FacePipelines,
    scene: Arc<crate::frame_data::PreparedScene>,
    instances: Arc<InstanceTable>,
    camera: wgpu::BindGroup,
    /// The masked program's group 0 (with the compute rasteriser's buffer under it).
    mask_camera: wgpu::BindGroup,
    /// Group 3 of the plain and the masked programs.
    geometry: wgpu::BindGroup,
    mask_geometry: wgpu::BindGroup,
    sequence: wgpu::Buffer,
    list: crate::frame_data::SceneDrawList,
    depth: Handle<Texture>,
    /// The ID target (the hardware raster's; none under the compute rasteriser).
    ids: Option<Handle<Texture>>,
    /// The second half: keep what the first drew.
    load: bool,
    /// The compute raster's resolve, drawn first (the first half under the compute raster).
    resolve: Option<Resolve>,
    /// Under the compute raster: the opaque batches are the compute rasteriser's.
    masked_only: bool,
}

impl Recording {
    /// Clears depth (the hardware raster's first half; the IDs are loaded), or under the
    /// compute raster resolves its depths into every sample instead, then draws every batch
    /// of its list (only the masked ones, into the compute raster's buffer, under the compute
    /// raster), through the sequence index buffer.
    fn record(&self, ctx: &mut PassContext<'_>) {
        let depth_view = ctx.texture(self.depth).create_view(&Default::default());
        let ids_view = self
            .ids
            .map(|ids| ctx.texture(ids).create_view(&Default::default()));
        let ids_attachment = ids_view
            .as_ref()
            .map(|view| wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    // Never cleared: a sample no triangle covers keeps an old ID, and its
                    // cleared depth (1.0) tells every reader it is sky. On chips whose
                    // fixed-function fill is slow, the clear cost a quarter of the pass
                    // (0.59 of 2.26 ms at MSAA 4 on the H200; BENCHMARKS.md).
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            });
        let mut pass = ctx.encoder.begin_render(&wgpu::RenderPassDescriptor {
            label: Some("visibility"),
            color_attachments: if ids_attachment.is_some() {
                std::slice::from_ref(&ids_attachment)
            } else {
                &[]
            },
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations {
                    // The second half keeps the first's depth; the compute rasteriser's
                    // resolve writes every sample, so its target is not cleared either.
                    load: if self.load || self.resolve.is_some() {
                        wgpu::LoadOp::Load
                    } else {
                        wgpu::LoadOp::Clear(1.0)
                    },
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if let Some(r) = &self.resolve {
            pass.set_pipeline(&r.pipeline);
            pass.set_bind_group(0, &r.group, &[]);
            pass.draw(0..3, 0..1);
        }
        let mut draws = SceneDraws::new(
            &mut pass,
            &self.scene,
            &self.instances,
            VertexStreams::Position,
        );
        // Drawn through the sequence: `vertex_index` is the position in the index buffer (plus
        // the base vertex), from which the shader pulls the vertex.
        draws
            .pass()
            .set_index_buffer(self.sequence.slice(..), wgpu::IndexFormat::Uint32);
        draws.draw_batches_with(&self.list, &self.instances, |batch| {
            if self.masked_only && !batch.masked {
                return None;
            }
            let (pipelines, group0, group3) = if batch.masked {
                (&self.masked, &self.mask_camera, &self.mask_geometry)
            } else {
                (&self.plain, &self.camera, &self.geometry)
            };
            Some(BatchState {
                pipeline: face_pipeline(pipelines, batch.double_sided, batch.mirrored),
                group2: batch.masked.then(|| self.scene.mask_group()),
                program_groups: Some((group0, Some(group3))),
            })
        });
    }
}
