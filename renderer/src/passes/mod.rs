//! The render passes, one module each, behind one contract: [`Pass`].
//!
//! A pass module owns everything about its pass: its pipelines (from the `shaders_gen`
//! variants) and its variant choice, its persistent GPU resources, its per-frame uniforms, and
//! the function that adds it to the frame graph. What several passes read lives below, in
//! [`crate::frame_data`]; a pass never imports `crate::frame`, which only runs an ordered list
//! of passes.
//!
//! Adding a pass: write its module here (a type implementing [`Pass`]), and put it in the pass
//! list of the paths that use it (`crate::frame`'s pass list) or, from an engine, insert it
//! with `Renderer::insert_pass_after`.

pub mod deferred;
pub mod depth_probe;
pub mod forward;
pub mod gpu_sort;
pub mod heatmap;
pub mod light_cull;
pub(crate) mod overlay_erase;
pub mod particles;
pub mod prez;
pub mod scene_cull;
pub mod shadow;
pub mod tonemap;
pub mod visibility;

use crate::frame_data::{FrameInputs, FrameReport, FrameResources, RenderError, SceneDrawList};
use crate::graph::RenderGraph;
use crate::graph::{PassEncoder, TimedPass};

/// Workgroups of 8×8 invocations that cover a `(width, height)` image, one invocation a texel.
pub(crate) fn groups_8x8((width, height): (u32, u32)) -> (u32, u32) {
    (width.div_ceil(8), height.div_ceil(8))
}

/// One pass of the frame. A frame calls, for every pass in list order: [`Pass::prepare`], then
/// [`Pass::add_to_graph`]; after the graph is recorded, [`Pass::after_execute`]; after the
/// frame is submitted, [`Pass::after_submit`].
pub trait Pass: std::fmt::Debug + std::any::Any {
    /// The pass's name: its graph node, its GPU timing label, and how engines find it.
    fn name(&self) -> &'static str;

    /// CPU work before the graph is built: write uniforms, upload items, (re)build resources
    /// the frame's inputs call for.
    fn prepare(&mut self, frame: &FrameInputs) -> Result<(), RenderError> {
        let _ = frame;
        Ok(())
    }

    /// Declares the pass on `graph`, reading what earlier passes left in `resources` and
    /// adding what it produces.
    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError>;

    /// Records work that follows the whole graph in the same submission (copies for readback).
    fn after_execute(
        &mut self,
        frame: &FrameInputs,
        resources: &FrameResources,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let _ = (frame, resources, encoder);
    }

    /// After the frame is submitted: start readbacks, pick up finished ones, and add the
    /// pass's section to the frame report.
    fn after_submit(&mut self, frame: &FrameInputs, report: &mut FrameReport) {
        let _ = (frame, report);
    }
}

/// Records draws of a prepared scene into a render pass: the scene's shared vertex streams,
/// index buffer and draw records (group 1) are bound once, and a pipeline or a group-2 bind
/// group is set only where it changes from the previous draw. Every pass that draws the scene
/// (pre-Z, forward, G-buffer, shadow casters) records through it.
pub(crate) struct SceneDraws<'p, 'a> {
    pass: &'p mut wgpu::RenderPass<'a>,
    pipeline: Option<&'a wgpu::RenderPipeline>,
    group2: Option<&'a wgpu::BindGroup>,
    /// The material program's groups 0 and 3 last set ([`BatchState::program_groups`]).
    group0: Option<&'a wgpu::BindGroup>,
    group3: Option<&'a wgpu::BindGroup>,
}

/// What a batch draws with: its pipeline, the scene's group 2 (if the pipeline has one), and,
/// for the passes that shade with material programs, the program's group 0
/// (`passes::forward::programs`, with its parameter records), and the visibility raster's
/// group 3 (the scene's geometry).
pub(crate) struct BatchState<'a> {
    pub(crate) pipeline: &'a wgpu::RenderPipeline,
    pub(crate) group2: Option<&'a wgpu::BindGroup>,
    pub(crate) program_groups: Option<(&'a wgpu::BindGroup, Option<&'a wgpu::BindGroup>)>,
}

impl<'p, 'a> SceneDraws<'p, 'a> {
    /// Binds `scene`'s `streams` and `instances`' draw records on `pass`.
    pub(crate) fn new(
        pass: &'p mut wgpu::RenderPass<'a>,
        scene: &'a crate::frame_data::PreparedScene,
        instances: &'a crate::frame_data::InstanceTable,
        streams: crate::scene::VertexStreams,
    ) -> Self {
        scene.gpu.bind_streams(pass, streams);
        pass.set_bind_group(1, &instances.draw_group, &[]);
        Self {
            pass,
            pipeline: None,
            group2: None,
            group0: None,
            group3: None,
        }
    }

    /// The render pass, for state outside the scene's draws (viewports, scissors).
    pub(crate) fn pass(&mut self) -> &mut wgpu::RenderPass<'a> {
        self.pass
    }

    /// Draws `geometry` with `pipeline` and `group2` as instance `instance`, the index the
    /// vertex shader reads its record by (a draw's index in `InstanceTable::draws`, or a
    /// shadow cast's).
    pub(crate) fn draw(
        &mut self,
        pipeline: &'a wgpu::RenderPipeline,
        group2: Option<&'a wgpu::BindGroup>,
        geometry: crate::scene::GpuPrimitive,
        instance: u32,
    ) {
        self.set_state(pipeline, group2);
        self.pass.draw_indexed(
            geometry.indices(),
            geometry.base_vertex,
            instance..instance + 1,
        );
    }

    /// Draws every batch of `list` with the pipeline and group 2 `state` picks for it: one
    /// multi-draw of its slots' indirect arguments (the slots culling left out draw no
    /// instance; where they are packed, of its drawn slots only, as many as its count), or, on a device that cannot draw indirectly with a first instance, each slot
    /// directly (empty slots skipped).
    pub(crate) fn draw_batches(
        &mut self,
        list: &'a SceneDrawList,
        instances: &'a crate::frame_data::InstanceTable,
        mut state: impl FnMut(
            &crate::frame_data::DrawBatch,
        ) -> (&'a wgpu::RenderPipeline, Option<&'a wgpu::BindGroup>),
    ) {
        self.draw_batches_with(list, instances, |batch| {
            let (pipeline, group2) = state(batch);
            Some(BatchState {
                pipeline,
                group2,
                program_groups: None,
            })
        });
    }

    /// [`SceneDraws::draw_batches`] with the whole [`BatchState`] of each batch; a batch
    /// whose state is `None` is not drawn.
    pub(crate) fn draw_batches_with(
        &mut self,
        list: &'a SceneDrawList,
        instances: &'a crate::frame_data::InstanceTable,
        mut state: impl FnMut(&crate::frame_data::DrawBatch) -> Option<BatchState<'a>>,
    ) {
        for (b, batch) in list.layout.batches.iter().enumerate() {
            let Some(state) = state(batch) else {
                continue;
            };
            if let Some((group0, group3)) = state.program_groups {
                self.set_program_groups(group0, group3);
            }
            let (pipeline, group2) = (state.pipeline, state.group2);
            let (slot, buffer) = (u64::from(batch.first_slot), &list.args_buffer);
            if let Some(counts) = list.counts.as_ref().filter(|_| list.indirect) {
                let count_at = (counts, 4 * b as u64);
                self.multi_draw_count((pipeline, group2), buffer, slot, count_at, batch.slot_count);
            } else if list.indirect {
                self.multi_draw(pipeline, group2, buffer, slot, batch.slot_count);
            } else {
                for slot in batch.slots() {
                    let d = list.layout.slot_draws[slot as usize];
                    if let Some(draw) = instances.draws.get(d as usize) {
                        self.draw(pipeline, group2, draw.geometry, d);
                    }
                }
            }
        }
    }

    /// Draws with `pipeline` and `group2` the `count` indirect arguments of `args` from
    /// `first` on (five words each).
    pub(crate) fn multi_draw(
        &mut self,
        pipeline: &'a wgpu::RenderPipeline,
        group2: Option<&'a wgpu::BindGroup>,
        args: &'a wgpu::Buffer,
        first: u64,
        count: u32,
    ) {
        self.set_state(pipeline, group2);
        let offset = first * SceneDrawList::ARGS_BYTES;
        self.pass.multi_draw_indexed_indirect(args, offset, count);
    }

    /// [`Self::multi_draw`] of at most `max` arguments, as many as the count at `count_at`
    /// (bytes) of `counts` says.
    pub(crate) fn multi_draw_count(
        &mut self,
        (pipeline, group2): (&'a wgpu::RenderPipeline, Option<&'a wgpu::BindGroup>),
        args: &'a wgpu::Buffer,
        first: u64,
        (counts, count_at): (&'a wgpu::Buffer, u64),
        max: u32,
    ) {
        self.set_state(pipeline, group2);
        let offset = first * SceneDrawList::ARGS_BYTES;
        (self.pass).multi_draw_indexed_indirect_count(args, offset, counts, count_at, max);
    }

    /// Sets a material program's group 0 and group 3 where they change.
    pub(crate) fn set_program_groups(
        &mut self,
        group0: &'a wgpu::BindGroup,
        group3: Option<&'a wgpu::BindGroup>,
    ) {
        if !self.group0.is_some_and(|g| std::ptr::eq(g, group0)) {
            self.pass.set_bind_group(0, group0, &[]);
            self.group0 = Some(group0);
        }
        if let Some(group) = group3
            && !self.group3.is_some_and(|g| std::ptr::eq(g, group))
        {
            self.pass.set_bind_group(3, group, &[]);
            self.group3 = Some(group);
        }
    }

    fn set_state(
        &mut self,
        pipeline: &'a wgpu::RenderPipeline,
        group2: Option<&'a wgpu::BindGroup>,
    ) {
        if !self.pipeline.is_some_and(|p| std::ptr::eq(p, pipeline)) {
            self.pass.set_pipeline(pipeline);
            self.pipeline = Some(pipeline);
        }
        if let Some(group) = group2
            && !self.group2.is_some_and(|g| std::ptr::eq(g, group))
        {
            self.pass.set_bind_group(2, group, &[]);
            self.group2 = Some(group);
        }
    }
}

/// The vertex streams of `vs_forward` (forward and G-buffer): position, normal, `TEXCOORD_0`,
/// tangent, `TEXCOORD_1`, `COLOR_0` (`VertexStreams::Forward`).
pub(crate) const FORWARD_STREAMS: [wgpu::VertexFormat; 6] = [
    wgpu::VertexFormat::Float32x3,
    wgpu::VertexFormat::Float32x3,
    wgpu::VertexFormat::Float32x2,
    wgpu::VertexFormat::Float32x4,
    wgpu::VertexFormat::Float32x2,
    wgpu::VertexFormat::Float32x4,
];

/// The vertex streams of the masked depth passes (pre-Z and shadow casters): position,
/// `TEXCOORD_0`, `TEXCOORD_1`, `COLOR_0` (`VertexStreams::Mask`).
pub(crate) const MASK_STREAMS: [wgpu::VertexFormat; 4] = [
    wgpu::VertexFormat::Float32x3,
    wgpu::VertexFormat::Float32x2,
    wgpu::VertexFormat::Float32x2,
    wgpu::VertexFormat::Float32x4,
];

/// Vertex buffer layouts of tightly packed attributes at locations 0.., one buffer each.
fn vertex_streams(formats: &[wgpu::VertexFormat]) -> Vec<[wgpu::VertexAttribute; 1]> {
    formats
        .iter()
        .enumerate()
        .map(|(location, &format)| {
            [wgpu::VertexAttribute {
                format,
                offset: 0,
                shader_location: location as u32,
            }]
        })
        .collect()
}

/// The `wgpu::VertexBufferLayout`s of [`vertex_streams`].
fn stream_layouts(
    streams: &[[wgpu::VertexAttribute; 1]],
) -> Vec<Option<wgpu::VertexBufferLayout<'_>>> {
    streams
        .iter()
        .map(|a| {
            Some(wgpu::VertexBufferLayout {
                array_stride: a[0].format.size(),
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: a,
            })
        })
        .collect()
}

/// What differs between the pipelines of passes that draw the scene's meshes (pre-Z, forward;
/// later shadows and the G-buffer).
pub(crate) struct MeshPipeline<'a> {
    pub label: &'a str,
    pub vertex_entry: &'a str,
    /// One tightly packed attribute per buffer, at locations 0.. in order.
    pub streams: &'a [wgpu::VertexFormat],
    pub double_sided: bool,
    /// For mirrored draws (`DrawItem::mirrored`): front faces wind clockwise (glTF 2.0), which
    /// both the culling and `front_facing` follow.
    pub mirrored: bool,
    /// The depth test; `None` for a pipeline drawn without a depth target.
    pub depth: Option<wgpu::DepthStencilState>,
    pub msaa: u32,
    /// The fragment entry point and its colour targets; `None` draws depth only.
    pub fragment: Option<(&'a str, &'a [Option<wgpu::ColorTargetState>])>,
}

/// A scene-mesh pipeline of `program`.
pub(crate) fn mesh_pipeline(
    device: &wgpu::Device,
    program: &crate::shader::ShaderProgram,
    p: &MeshPipeline<'_>,
) -> wgpu::RenderPipeline {
    let streams = vertex_streams(p.streams);
    program.render_pipeline(
        device,
        &wgpu::RenderPipelineDescriptor {
            label: Some(p.label),
            layout: Some(&program.pipeline_layout),
            vertex: wgpu::VertexState {
                module: &program.module,
                entry_point: Some(p.vertex_entry),
                compilation_options: Default::default(),
                buffers: &stream_layouts(&streams),
            },
            primitive: wgpu::PrimitiveState {
                front_face: front_face(p.mirrored),
                cull_mode: cull_mode(p.double_sided),
                ..Default::default()
            },
            depth_stencil: p.depth.clone(),
            multisample: wgpu::MultisampleState {
                count: p.msaa,
                ..Default::default()
            },
            fragment: p.fragment.map(|(entry, targets)| wgpu::FragmentState {
                module: &program.module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                targets,
            }),
            multiview_mask: None,
            cache: None,
        },
    )
}

/// Depth test state on [`crate::frame_data::DEPTH_FORMAT`].
pub(crate) fn depth_state(write: bool, compare: wgpu::CompareFunction) -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: crate::frame_data::DEPTH_FORMAT,
        depth_write_enabled: Some(write),
        depth_compare: Some(compare),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// A mesh pass's pipelines for every (double-sided, mirrored) pair, `[double_sided][mirrored]`.
pub(crate) type FacePipelines = [[wgpu::RenderPipeline; 2]; 2];

/// [`FacePipelines`] from `make(double_sided, mirrored)`.
pub(crate) fn face_pipelines(make: impl Fn(bool, bool) -> wgpu::RenderPipeline) -> FacePipelines {
    [false, true].map(|double_sided| [false, true].map(|mirrored| make(double_sided, mirrored)))
}

/// The pipeline of `pipelines` for a draw of a `double_sided` material, `mirrored` or not.
pub(crate) fn face_pipeline(
    pipelines: &FacePipelines,
    double_sided: bool,
    mirrored: bool,
) -> &wgpu::RenderPipeline {
    &pipelines[usize::from(double_sided)][usize::from(mirrored)]
}

/// Counter-clockwise front faces, clockwise where the draw is mirrored.
fn front_face(mirrored: bool) -> wgpu::FrontFace {
    if mirrored {
        wgpu::FrontFace::Cw
    } else {
        wgpu::FrontFace::Ccw
    }
}

/// Back-face culling unless the material is double-sided.
fn cull_mode(double_sided: bool) -> Option<wgpu::Face> {
    (!double_sided).then_some(wgpu::Face::Back)
}

/// A full-screen triangle pipeline (`vs_fullscreen` + `fragment`) into one `format` target.
pub(crate) fn fullscreen_pipeline(
    device: &wgpu::Device,
    program: &crate::shader::ShaderProgram,
    fragment: &str,
    format: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    program.render_pipeline(
        device,
        &wgpu::RenderPipelineDescriptor {
            label: Some(fragment),
            layout: Some(&program.pipeline_layout),
            vertex: wgpu::VertexState {
                module: &program.module,
                entry_point: Some("vs_fullscreen"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &program.module,
                entry_point: Some(fragment),
                compilation_options: Default::default(),
                targets: &[Some(format.into())],
            }),
            multiview_mask: None,
            cache: None,
        },
    )
}

/// A render pass over one colour attachment (loaded or cleared as `load` says, and stored),
/// without depth.
pub(crate) fn color_pass<'e>(
    encoder: &'e mut PassEncoder<'_>,
    label: &str,
    view: &wgpu::TextureView,
    load: wgpu::LoadOp<wgpu::Color>,
) -> TimedPass<'e, wgpu::RenderPass<'e>> {
    encoder.begin_render(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load,
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// Draws the full-screen triangle of `pipeline` into `target` (cleared to black, by
/// [`color_pass`]) with group 0 as its module's generated builder built it (nothing, after
/// keeping the error in `ctx`, where it could not).
pub(crate) fn draw_fullscreen(
    ctx: &mut crate::graph::PassContext<'_>,
    label: &str,
    pipeline: &wgpu::RenderPipeline,
    group: Result<wgpu::BindGroup, shader_bind::BindError>,
    target: &wgpu::TextureView,
) {
    let Some(bind_group) = ctx.bind(group) else {
        return;
    };
    let black = wgpu::LoadOp::Clear(wgpu::Color::BLACK);
    let mut pass = color_pass(&mut ctx.encoder, label, target, black);
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, &bind_group, &[]);
    pass.draw(0..3, 0..1);
}
