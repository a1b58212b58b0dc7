//! Blended surfaces over the compute rasteriser's frame
//! ([`crate::frame_data::RendererConfig::reads_compute_samples`]), lit in compute
//! (`shaders_gen::visibility::vis_blend`, glTF PBR's `blend` variant at the frame's `msaa`):
//!
//! 1. **`blended fragments`** zeroes the per-pixel lists and draws the blended draws back to
//!    front with `vs_blend` (vertices pulled through the visibility frame's sequence index
//!    buffer, so each fragment knows its triangle) and `fs_blend_list`, which lists every
//!    fragment in front of the opaque surface, over a scratch depth target neither loaded nor
//!    stored (no colour target, no depth test).
//! 2. **`blended lighting`** runs `vis_blend_args` (the lighting's dispatch and the forward
//!    pass's choice of pipeline, into the lists' header, copied into a small indirect buffer)
//!    and `vis_shade_blended`, one invocation a listed fragment: rebuilt from its triangle,
//!    shaded by glTF PBR's surface, lit, its colour stored in its record.
//! 3. The forward pass draws the blended draws again through `vs_blend`, with two count-draws
//!    whose counts the GPU wrote: `fs_blend_listed`, which outputs each fragment's record's
//!    colour into the samples where it is in front of the opaque surface (its `sample_mask`),
//!    so the hardware blends them in order; or, where fragments came past the records'
//!    capacity ([`crate::frame_data::RendererConfig::blended_fragment_records`]),
//!    `fs_forward_vis64`, which shades those itself (and always on a device that cannot
//!    count draws). The pass has no depth target.
//!
//! On the H200 the fragment stage is a few of the chip's SMs: lit there, the courtyard's glass
//! cost 0.79 ms at MSAA 4, of which 0.71 was its lighting (BENCHMARKS.md).

use std::sync::{Arc, Mutex, PoisonError};

use shaders_gen::visibility::{vis_blend, vis_frame};

use super::bindings::FrameGroup;
use super::record::draw_blended;
use crate::frame_data::{
    ConfigError, DEPTH_FORMAT, FrameInputs, FrameResources, RenderError, SceneDrawList,
    VisibilityHandles, VisibilitySamples,
};
use crate::graph::{
    Buffer, BufferAccess, Handle, ImportAccess, PassBuilder, PassContext, RenderGraph,
    TextureAccess, TextureDesc,
};
use crate::passes::visibility::geometry::geometry_group;
use crate::passes::visibility::resolve::not_loaded;
use crate::passes::{MeshPipeline, SceneDraws, depth_state, mesh_pipeline};
use crate::scene::VertexStreams;
use crate::shader::ShaderProgram;

/// The blended program's own pipelines (the listing and the lighting kernel), its `VisParams`
/// uniform, and the lists and records it keeps between frames.
#[derive(Debug)]
pub(crate) struct OverSamples {
    params: wgpu::Buffer,
    program: ShaderProgram,
    list: wgpu::RenderPipeline,
    /// `vis_blend_args` and `vis_shade_blended`.
    shade: [wgpu::ComputePipeline; 2],
    kept: Mutex<Option<ListBuffers>>,
}

/// The per-pixel lists (`BLEND_LISTS`: a header, then a head a pixel), the records
/// (`BLEND_RECORDS`) and the indirect arguments the header's are copied into.
#[derive(Debug, Clone)]
struct ListBuffers {
    lists: wgpu::Buffer,
    records: wgpu::Buffer,
    args: wgpu::Buffer,
}

/// The header's words from the lighting's dispatch to the draw counts (`BLEND_LISTS[1..6]`),
/// copied into `args`: its byte offset in the lists and size.
const ARGS_IN_LISTS: u64 = 4;
const ARGS_BYTES: u64 = 20;
/// The draw count of the pipeline that outputs records (`fs_blend_listed`) in `args`, and of
/// the one that may shade (`fs_forward_vis64`).
pub(crate) const LISTED_DRAWS_AT: u64 = 12;
pub(crate) const SHADED_DRAWS_AT: u64 = 16;
/// The most records one dispatch of 64-invocation workgroups lights.
const MAX_RECORDS: u64 = 65_535 * 64;

impl ListBuffers {
    fn new(device: &wgpu::Device, pixels: u64, records: u64) -> Self {
        use wgpu::BufferUsages as U;
        let (lists, records) = Self::sizes(pixels, records);
        let buffer = |label, size, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        Self {
            lists: buffer(
                "blended lists",
                lists,
                U::STORAGE | U::COPY_DST | U::COPY_SRC,
            ),
            records: buffer("blended records", records, U::STORAGE),
            args: buffer("blended arguments", ARGS_BYTES, U::INDIRECT | U::COPY_DST),
        }
    }

    /// The sizes in bytes of the lists and the records for `pixels` and `records` (at least
    /// one, at most [`MAX_RECORDS`]).
    fn sizes(pixels: u64, records: u64) -> (u64, u64) {
        let header = u64::from(vis_blend::BLEND_LIST_HEADER);
        (
            (header + pixels) * 4,
            records.clamp(1, MAX_RECORDS) * size_of::<vis_blend::BlendRecord>() as u64,
        )
    }

    fn matches(&self, sizes: (u64, u64)) -> bool {
        (self.lists.size(), self.records.size()) == sizes
    }
}

/// One frame's inputs of the blended program.
#[derive(Clone)]
pub(crate) struct FrameSamples {
    params: wgpu::Buffer,
    samples: Handle<Buffer>,
    /// The lists and records, as the listing and lighting passes left them.
    lists: Handle<Buffer>,
    records: Handle<Buffer>,
    buffers: ListBuffers,
    /// Groups 1 to 3 and the sequence index buffer of the blended draws.
    pub(crate) draws: Arc<BlendedGroups>,
}

/// What the blended program's draws bind beside group 0: its groups 1 (draw records),
/// 2 (materials) and 3 (the scene's geometry), and the index buffer they are drawn over.
pub(crate) struct BlendedGroups {
    pub(crate) records: wgpu::BindGroup,
    pub(crate) materials: wgpu::BindGroup,
    pub(crate) geometry: wgpu::BindGroup,
    /// The sequence index buffer (`vs_blend` pulls its vertices).
    pub(crate) sequence: wgpu::Buffer,
}

impl BlendedGroups {
    /// Binds `group0` and groups 1 and 3 on `draws`' pass (after `SceneDraws::new`; group 2
    /// goes with each draw).
    pub(crate) fn bind<'a>(&'a self, draws: &mut SceneDraws<'_, 'a>, group0: &'a wgpu::BindGroup) {
        draws.set_program_groups(group0, Some(&self.geometry));
        draws.pass().set_bind_group(1, &self.records, &[]);
    }

    /// [`Self::bind`], and the sequence index buffer, for `vs_blend`.
    pub(crate) fn bind_pulled<'a>(
        &'a self,
        draws: &mut SceneDraws<'_, 'a>,
        group0: &'a wgpu::BindGroup,
    ) {
        self.bind(draws, group0);
        (draws.pass()).set_index_buffer(self.sequence.slice(..), wgpu::IndexFormat::Uint32);
    }
}

impl OverSamples {
    /// The listing pipeline and the lighting kernel of `program` (glTF PBR's blended variant)
    /// at `msaa` samples.
    pub(crate) fn new(
        device: &wgpu::Device,
        program: &ShaderProgram,
        msaa: u32,
    ) -> Result<Self, RenderError> {
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("blended over samples"),
            size: size_of::<vis_frame::VisParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let list = mesh_pipeline(
            device,
            program,
            &MeshPipeline {
                label: "blended fragments",
                vertex_entry: "vs_blend",
                streams: &[],
                // No face culled: `fs_blend_list` drops single-sided back faces itself, as the
                // forward pass's blended pipeline does.
                double_sided: true,
                mirrored: false,
                depth: Some(depth_state(false, wgpu::CompareFunction::Always)),
                msaa,
                fragment: Some(("fs_blend_list", &[])),
            },
        );
        Ok(Self {
            params,
            list,
            shade: [
                program.compute_pipeline(device, "vis_blend_args")?,
                program.compute_pipeline(device, "vis_shade_blended")?,
            ],
            program: program.clone(),
            kept: Mutex::new(None),
        })
    }

    /// This frame's inputs, after writing the uniform; with blended draws in `draws`, the
    /// listing and lighting passes added to `graph`. An error where the frame has no compute
    /// rasteriser's samples (the visibility pass did not run before).
    pub(crate) fn frame(
        &self,
        graph: &mut RenderGraph,
        (frame, resources): (&FrameInputs, &mut FrameResources),
        (group, draws): (&FrameGroup, &SceneDrawList),
    ) -> Result<FrameSamples, RenderError> {
        let missing = || {
            RenderError::Config(ConfigError::MissingInput {
                pass: "forward",
                input: "the compute rasteriser's samples",
            })
        };
        let vis = resources.visibility.clone().ok_or_else(missing)?;
        let VisibilitySamples::Buffer { samples } = vis.samples else {
            return Err(missing());
        };
        self.write_params(frame, &vis, draws);
        let device = frame.gpu.device();
        let buffers = self.buffers(frame);
        let mut import =
            |name, buffer| resources.import_buffer(graph, name, buffer, ImportAccess::ReadWrite);
        let lists = import("blended lists", &buffers.lists);
        let records = import("blended records", &buffers.records);
        let blended = Arc::new(BlendedGroups {
            records: frame.instances.draw_group_for(device, &self.program)?,
            materials: frame.scene.material_group_for(device, &self.program)?,
            geometry: geometry_group(device, &self.program, &frame.scene, &vis.draw_geometry)?,
            sequence: vis.sequence.clone(),
        });
        let mut inputs = FrameSamples {
            params: self.params.clone(),
            samples,
            lists,
            records,
            buffers,
            draws: blended,
        };
        self.add_listing(graph, frame, (group, draws), &mut inputs);
        self.add_lighting(graph, group, &mut inputs);
        Ok(inputs)
    }

    /// `blended fragments`: the lists zeroed, then the blended draws through `vs_blend` and
    /// `fs_blend_list` over a scratch depth target.
    fn add_listing(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        (group, draws): (&FrameGroup, &SceneDrawList),
        inputs: &mut FrameSamples,
    ) {
        let c = &frame.config;
        let desc = TextureDesc::new_2d(c.width, c.height, DEPTH_FORMAT).with_samples(c.msaa);
        let mut scratch = graph.create_texture("blended fragments depth", desc);
        let mut pass = graph.add_pass("blended fragments");
        group.read_by(&mut pass);
        pass.read_buffer(inputs.samples, BufferAccess::StorageRead)
            .read_buffer(draws.args, BufferAccess::Indirect)
            .write_texture(&mut scratch, TextureAccess::DepthWrite)
            .write_buffer(&mut inputs.lists, BufferAccess::StorageWrite)
            .write_buffer(&mut inputs.records, BufferAccess::StorageWrite);
        if let crate::frame_data::BlendedDraws::Sorted { args, .. } = &draws.blended {
            pass.read_buffer(*args, BufferAccess::Indirect);
        }
        // The closure binds the buffers themselves; the handles order the passes after.
        let listing = (inputs.clone(), group.clone(), self.list.clone());
        let (scene, instances) = (Arc::clone(&frame.scene), Arc::clone(&frame.instances));
        let (program, draw_list) = (self.program.clone(), draws.clone());
        pass.execute(move |ctx| {
            let (inputs, group, pipeline) = &listing;
            ctx.encoder.clear_buffer(&inputs.buffers.lists, 0, None);
            let Some(group0) = inputs.bind_group(ctx, group, &program) else {
                return;
            };
            let view = ctx.texture(scratch).create_view(&Default::default());
            let mut pass = ctx.encoder.begin_render(&wgpu::RenderPassDescriptor {
                label: Some("blended fragments"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &view,
                    depth_ops: Some(wgpu::Operations {
                        load: not_loaded(),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            let mut draws = SceneDraws::new(&mut pass, &scene, &instances, VertexStreams::Position);
            inputs.draws.bind_pulled(&mut draws, &group0);
            let materials = Some(&inputs.draws.materials);
            draw_blended(&mut draws, (&draw_list, &instances), pipeline, materials);
        });
    }

    /// `blended lighting`: the arguments, then `vis_shade_blended` over the listed records.
    fn add_lighting(&self, graph: &mut RenderGraph, group: &FrameGroup, inputs: &mut FrameSamples) {
        let mut pass = graph.add_pass("blended lighting");
        group.read_by(&mut pass);
        pass.read_buffer(inputs.samples, BufferAccess::StorageRead)
            .read_buffer(inputs.lists, BufferAccess::StorageRead)
            .write_buffer(&mut inputs.records, BufferAccess::StorageWrite);
        let (inputs, group) = (inputs.clone(), group.clone());
        let (program, [args, shade]) = (self.program.clone(), self.shade.clone());
        pass.execute(move |ctx| {
            let Some(group0) = inputs.bind_group(ctx, &group, &program) else {
                return;
            };
            let (d, b) = (&inputs.draws, &inputs.buffers);
            let groups = [&group0, &d.records, &d.materials, &d.geometry];
            for (pipeline, indirect) in [(&args, false), (&shade, true)] {
                if indirect {
                    // The header is bound read-write to every entry point: a dispatch reads a
                    // copy.
                    let (lists, at) = (&b.lists, ARGS_IN_LISTS);
                    ctx.encoder
                        .copy_buffer_to_buffer(lists, at, &b.args, 0, ARGS_BYTES);
                }
                let mut pass = ctx.encoder.begin_compute("blended lighting");
                pass.set_pipeline(pipeline);
                for (index, group) in groups.iter().enumerate() {
                    pass.set_bind_group(index as u32, *group, &[]);
                }
                if indirect {
                    pass.dispatch_workgroups_indirect(&b.args, 0);
                } else {
                    pass.dispatch_workgroups(1, 1, 1);
                }
            }
        });
    }

    /// The frame's `VisParams`: what `vis_point` rebuilds a fragment with, the screen, and the
    /// blended draws of `draws`.
    fn write_params(&self, frame: &FrameInputs, vis: &VisibilityHandles, draws: &SceneDrawList) {
        let blended = match &draws.blended {
            crate::frame_data::BlendedDraws::Sorted { count, .. } => *count,
            crate::frame_data::BlendedDraws::Listed(list) => list.len() as u32,
        };
        let cam = &frame.camera;
        let uniform = vis_frame::VisParams::new(
            (cam.projection * cam.view).inverse(),
            frame.config.sky,
            vis.draws,
            frame.screen(),
            0,
            0,
            0,
            blended,
            glam::UVec2::ZERO,
        );
        frame
            .gpu
            .queue()
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&uniform));
    }

    /// The lists and records for this frame's size and capacity, made again when either
    /// changes.
    fn buffers(&self, frame: &FrameInputs) -> ListBuffers {
        let c = &frame.config;
        let pixels = u64::from(c.width) * u64::from(c.height);
        let records = match c.blended_fragment_records {
            0 => pixels.div_ceil(2),
            n => u64::from(n),
        };
        let wanted = ListBuffers::sizes(pixels, records);
        let mut kept = self.kept.lock().unwrap_or_else(PoisonError::into_inner);
        match kept.as_ref() {
            Some(b) if b.matches(wanted) => b.clone(),
            _ => kept
                .insert(ListBuffers::new(frame.gpu.device(), pixels, records))
                .clone(),
        }
    }
}

impl FrameSamples {
    /// The indirect buffer whose words [`LISTED_DRAWS_AT`] and [`SHADED_DRAWS_AT`] count the
    /// blended draws of the forward pass's two pipelines.
    pub(crate) fn draw_counts(&self) -> &wgpu::Buffer {
        &self.buffers.args
    }

    /// Declares `pass`'s reads of the samples, the lists and the records.
    pub(crate) fn read_by(&self, pass: &mut PassBuilder<'_>) {
        pass.read_buffer(self.samples, BufferAccess::StorageRead)
            .read_buffer(self.lists, BufferAccess::StorageRead)
            .read_buffer(self.records, BufferAccess::StorageRead);
    }

    /// Group 0 of `program` (the blended variant): `group`'s parts, the samples, the lists
    /// and the records; `None` after recording the error in `ctx`.
    pub(crate) fn bind_group(
        &self,
        ctx: &mut PassContext<'_>,
        group: &FrameGroup,
        program: &ShaderProgram,
    ) -> Option<wgpu::BindGroup> {
        let b = &self.buffers;
        let buffers = [
            ctx.buffer(self.samples).clone(),
            b.lists.clone(),
            b.records.clone(),
        ];
        group.over_samples_bind_group(ctx, program, (&self.params, &buffers))
    }
}
