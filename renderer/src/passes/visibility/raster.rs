//! The visibility raster pass: every opaque and alpha-masked draw of the scene's batches into
//! the multisampled depth buffer and the visibility buffer (`shaders_gen`'s `vis_raster`). With
//! [`VisibilityRaster::Compute`] the compute rasteriser draws the opaque ones first
//! (`super::compute_raster`) into its buffer, which is then the frame's visibility samples
//! ([`VisibilitySamples::Buffer`]): this pass adds the alpha-masked draws to it with the same
//! 64-bit atomics (`vis_raster`'s `vis64` variant), over a scratch depth target it neither
//! loads nor stores (`LoadOp::DontCare`), and adds nothing without masked draws. A pass of its own resolves the buffer's
//! depths into a depth target (`super::resolve`) for a pass that reads one; the frame's own
//! passes read the buffer, and the graph leaves the resolve out.
//!
//! The depth is cleared and the ID target only loaded: a sample at depth 1.0 is sky whatever
//! ID it holds, and every reader of the IDs tests the depth first (`vis_frame::vis_id_at`).

use std::sync::{Arc, Mutex, PoisonError};

use shaders_gen::visibility::vis_raster;

use super::compute_raster::RasterHalf;
use super::geometry::{
    SceneState, draw_geometry, draw_geometry_buffer, geometry_group, sequence_buffer,
};
use super::raster_draws::{RasterTargets, Recording};
use super::resolve::{ComputeStage, not_loaded};
use crate::GpuContext;
use crate::frame_data::{
    ConfigError, DEPTH_FORMAT, FrameInputs, FrameResources, RenderError, RendererConfig,
    SceneDrawList, VISIBILITY_FORMAT, VisibilityHandles, VisibilityRaster, VisibilitySamples,
};
use crate::graph::{BufferAccess, Handle, RenderGraph, Texture, TextureAccess, TextureDesc};
use crate::passes::{
    FacePipelines, MeshPipeline, Pass, depth_state, face_pipelines, mesh_pipeline,
};
use crate::shader::ShaderProgram;

/// The visibility raster pass: its programs and pipelines (`[double_sided][mirrored]`, plain
/// and alpha-masked). With occlusion culling it runs twice, as pre-Z does: first the draws
/// visible last frame into cleared depth (the IDs are loaded; under the compute rasteriser,
/// its raster and the masked draws merged into its buffer); then ([`VisRasterPass::late`], after
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
        // The renderer makes `Auto` concrete before it builds passes; left as it is, it reads as
        // the hardware raster, as `RendererConfig::reads_compute_samples` does.
        let compute = match config.visibility_raster {
            VisibilityRaster::Auto | VisibilityRaster::Hardware => None,
            VisibilityRaster::Compute => Some(ComputeStage::new(gpu, config)?),
        };
        // Under the compute rasteriser the masked draws add their samples to its buffer.
        let vis64 = compute.is_some();
        let (program, mask_program) = raster_programs(gpu, config, vis64)?;
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
                        // The masked draws over the compute rasteriser's buffer: its 64-bit
                        // atomics keep the nearest sample, and the scratch depth target they
                        // are drawn over is neither loaded nor stored.
                        depth: Some(if masked && vis64 {
                            depth_state(false, wgpu::CompareFunction::Always)
                        } else {
                            depth_state(true, wgpu::CompareFunction::Less)
                        }),
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
    /// A recording of `list`'s batches into `targets`, with the geometry records
    /// `draw_geometry` (and, for the masked draws under the compute rasteriser, its buffer
    /// `vis64`) and the sequence index buffer.
    fn recording(
        &self,
        frame: &FrameInputs,
        (draw_geometry, vis64): (&wgpu::Buffer, Option<&wgpu::Buffer>),
        sequence: wgpu::Buffer,
        list: &SceneDrawList,
        targets: RasterTargets,
    ) -> Result<Recording, RenderError> {
        let [camera, mask_camera, geometry, mask_geometry] =
            self.groups(frame, draw_geometry, vis64)?;
        Ok(Recording {
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
            targets,
        })
    }

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
                let params = vis_raster::SampleLayout::new(c.width, glam::UVec3::ZERO);
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
        if self.late {
            // The second half draws occlusion culling's late slots over the first's output.
            let Some(late) = list.late_half() else {
                return Ok(());
            };
            list = late;
        }
        let kept = self.kept_buffers().ok_or(missing(
            "draw geometry and sequence indices (built in prepare)",
        ))?;
        if let Some(stage) = &self.compute {
            return self.add_compute(graph, frame, resources, stage, (list, kept));
        }
        let (draw_geometry, draws, sequence) = kept;
        let first = if self.late {
            let depth = resources.depth.ok_or(missing("the first half's depth"))?;
            let vis = resources
                .visibility
                .clone()
                .ok_or(missing("the first half's visibility buffer"))?;
            Some((depth, vis.samples))
        } else {
            None
        };
        let (mut depth, mut samples) = match first {
            Some(kept) => kept,
            None => new_targets(graph, frame),
        };
        let targets = RasterTargets {
            depth,
            ids: match samples {
                VisibilitySamples::Targets { ids } => Some(ids),
                VisibilitySamples::Buffer { .. } => None,
            },
            depth_ops: if first.is_some() {
                (wgpu::LoadOp::Load, wgpu::StoreOp::Store)
            } else {
                (wgpu::LoadOp::Clear(1.0), wgpu::StoreOp::Store)
            },
            masked_only: false,
        };
        let recording = self.recording(
            frame,
            (&draw_geometry, None),
            sequence.clone(),
            &list,
            targets,
        )?;
        let mut pass = graph.add_pass(self.name());
        pass.read_buffer(list.args, BufferAccess::Indirect)
            .write_texture(&mut depth, TextureAccess::DepthWrite);
        if let VisibilitySamples::Targets { ids } = &mut samples {
            pass.write_texture(ids, TextureAccess::ColorAttachment);
        }
        pass.execute(move |ctx| recording.record(ctx));
        resources.depth = Some(depth);
        resources.visibility = Some(VisibilityHandles {
            samples,
            draw_geometry,
            draws,
            sequence,
        });
        Ok(())
    }
}

/// The plain program and the masked one (with `vis64`, the variant that merges into the compute
/// rasteriser's buffer, at the frame's sample count, which the compute stage checked).
fn raster_programs(
    gpu: &GpuContext,
    config: &RendererConfig,
    vis64: bool,
) -> Result<(ShaderProgram, ShaderProgram), RenderError> {
    let program = |alpha_mask, vis64| {
        let msaa = match vis64 {
            true => vis_raster::Msaa::from_value(config.msaa)
                .ok_or_else(|| ConfigError::shader_sample_count(config.msaa))?,
            false => vis_raster::Msaa::Msaa0,
        };
        let key = vis_raster::VariantKey {
            alpha_mask,
            vis64,
            msaa,
        };
        Ok::<_, RenderError>(gpu.program(vis_raster::variant(key)?)?)
    };
    Ok((program(false, false)?, program(true, vis64)?))
}

/// The first half's depth target and ID target (the hardware raster's).
fn new_targets(
    graph: &mut RenderGraph,
    frame: &FrameInputs,
) -> (Handle<Texture>, VisibilitySamples) {
    let c = &frame.config;
    let size = TextureDesc::new_2d(c.width, c.height, DEPTH_FORMAT).with_samples(c.msaa);
    let ids = TextureDesc::new_2d(c.width, c.height, VISIBILITY_FORMAT).with_samples(c.msaa);
    let samples = VisibilitySamples::Targets {
        ids: graph.create_texture("visibility", ids),
    };
    (graph.create_texture("depth", size), samples)
}

impl VisRasterPass {
    /// Under the compute rasteriser: its raster of the opaque draws (the first half), the
    /// masked draws of `list` merged into its buffer (a render pass of their own over a
    /// scratch depth target, neither loaded nor stored, which their pipelines do not test:
    /// their 64-bit atomics are the depth test), and the buffer's depths resolved into a new depth target
    /// ([`FrameResources::depth`]), which the graph leaves out of a frame that reads none.
    fn add_compute(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
        stage: &ComputeStage,
        (list, (draw_geometry, draws, sequence)): (
            SceneDrawList,
            (wgpu::Buffer, u32, wgpu::Buffer),
        ),
    ) -> Result<(), RenderError> {
        let half = if self.late {
            let first = resources.visibility.as_ref().map(|v| v.samples);
            let Some(VisibilitySamples::Buffer { samples }) = first else {
                return Err(RenderError::Config(ConfigError::MissingInput {
                    pass: "visibility (late)",
                    input: "the first half's compute-rasteriser samples",
                }));
            };
            RasterHalf::Late(samples)
        } else {
            RasterHalf::First
        };
        let (resolve, vis64) =
            stage.add_to_graph(graph, frame, resources, (&list, &draw_geometry), half)?;
        let mut samples = resolve.samples;
        if list.layout.batches.iter().any(|b| b.masked) {
            let c = &frame.config;
            let desc = TextureDesc::new_2d(c.width, c.height, DEPTH_FORMAT).with_samples(c.msaa);
            let mut scratch = graph.create_texture("visibility masked depth", desc);
            let targets = RasterTargets {
                depth: scratch,
                ids: None,
                depth_ops: (not_loaded(), wgpu::StoreOp::Discard),
                masked_only: true,
            };
            let buffers = (&draw_geometry, Some(&vis64));
            let recording = self.recording(frame, buffers, sequence.clone(), &list, targets)?;
            let mut pass = graph.add_pass(self.name());
            pass.read_buffer(list.args, BufferAccess::Indirect)
                .write_texture(&mut scratch, TextureAccess::DepthWrite)
                .write_buffer(&mut samples, BufferAccess::StorageWrite);
            pass.execute(move |ctx| recording.record(ctx));
        }
        resources.depth = Some(super::resolve::add_depth_resolve(
            graph, frame, resolve, samples,
        ));
        resources.visibility = Some(VisibilityHandles {
            samples: VisibilitySamples::Buffer { samples },
            draw_geometry,
            draws,
            sequence,
        });
        Ok(())
    }
}
