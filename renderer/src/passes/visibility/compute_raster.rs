//! The compute rasteriser (`shaders_gen`'s `vis_compute_raster`): the opaque triangles the
//! visibility raster pass draws, rasterised again by compute kernels into one 64-bit atomic a
//! sample, on adapters with `SHADER_INT64_ATOMIC_MIN_MAX`.
//!
//! With [`crate::frame_data::VisibilityRaster::Compute`] the visibility raster pass runs it
//! first, and its buffer is the frame's visibility samples
//! ([`crate::frame_data::VisibilitySamples::Buffer`]; `super::resolve` writes its depths into a
//! depth target for a pass that reads one). As a pass of its own ([`crate::extend::ComputeRasterPass`], inserted
//! with [`crate::frame::Renderer::insert_pass_after`] after `"visibility"`) it runs beside the
//! hardware raster, which the frame then reads: so the bench times both rasterisers on the
//! same frames (`cargo xtask bench --compute-raster`) and the tests compare their IDs
//! (`tests/tests/render_gpu/compute_raster.rs`); it then rasterises every opaque draw.
//! Inside the visibility raster pass it rasterises only the slots scene culling kept, once for
//! each half of occlusion culling ([`RasterHalf`]), as the hardware raster draws them.

use std::sync::{Arc, Mutex, PoisonError};

use shaders_gen::visibility::compute_raster::vis_compute_raster as kernels;

use super::compute_raster_buffers::{Buffers, Sizing};
use super::geometry::geometry_group;
use crate::frame_data::{
    BatchLayout, ConfigError, FrameInputs, FrameResources, NO_DRAW, RenderError, RendererConfig,
    SceneDrawList,
};
use crate::graph::TimedPass;
use crate::graph::{Buffer, BufferAccess, Handle, ImportAccess, PassContext, RenderGraph};
use crate::passes::Pass;
use crate::shader::ShaderProgram;
use crate::{GpuContext, GpuError};

/// What a frame of the compute rasteriser counted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ComputeRasterCounts {
    /// Triangles rasterised by tiles (their box over `small_area` pixels, or crossing the eye
    /// plane).
    pub large: u32,
    /// Tiles of those triangles.
    pub tiles: u32,
    /// Large triangles left out because the lists were full (0 in a correct frame).
    pub overflow: u32,
}

/// The compute rasteriser pass. Opt-in: insert it after `"visibility"`.
#[derive(Debug)]
pub struct ComputeRasterPass {
    program: ShaderProgram,
    triangles: wgpu::ComputePipeline,
    args: wgpu::ComputePipeline,
    late_args: wgpu::ComputePipeline,
    tiles: wgpu::ComputePipeline,
    params: wgpu::Buffer,
    msaa: u32,
    /// Pixel-box area up to which one invocation rasterises a triangle.
    small_area: u32,
    /// Whether every opaque draw is rasterised, whatever culling kept (the pass beside the
    /// hardware raster), or only the kept slots (inside the visibility raster pass).
    every_slot: bool,
    buffers: Arc<Mutex<Option<Buffers>>>,
}

/// The graph pass after the pass's own ([`Pass::name`]) that rasterises the large triangles'
/// tiles.
pub const TILES_PASS: &str = "compute raster tiles";
/// Occlusion culling's second half of the pass ([`RasterHalf::Late`]): the triangles, then
/// the tiles.
pub const LATE_PASS: &str = "compute raster (late)";
/// See [`LATE_PASS`].
pub const LATE_TILES_PASS: &str = "compute raster tiles (late)";
/// The default of [`ComputeRasterPass::with_small_area`].
pub const DEFAULT_SMALL_AREA: u32 = 64;

/// Which of the visibility raster's halves a compute raster is.
#[derive(Debug, Clone, Copy)]
pub(crate) enum RasterHalf {
    /// The first (or only) half: the samples are cleared first.
    First,
    /// Occlusion culling's second half: over the first's samples, this handle of them.
    Late(Handle<Buffer>),
}

impl ComputeRasterPass {
    /// The pass for `config`'s sample count, rasterising every opaque draw of the scene
    /// whatever culling kept; refused (the variant's error) on a device without 64-bit atomic
    /// min/max.
    pub fn new(gpu: &GpuContext, config: &RendererConfig) -> Result<Self, RenderError> {
        Self::with_culling(gpu, config, false)
    }

    /// The pass inside the visibility raster pass: only the slots its list keeps.
    pub(crate) fn culled(gpu: &GpuContext, config: &RendererConfig) -> Result<Self, RenderError> {
        Self::with_culling(gpu, config, true)
    }

    fn with_culling(
        gpu: &GpuContext,
        config: &RendererConfig,
        culled: bool,
    ) -> Result<Self, RenderError> {
        let msaa = kernels::Msaa::from_value(config.msaa)
            .ok_or_else(|| ConfigError::shader_sample_count(config.msaa))?;
        let program = gpu.program(kernels::variant(kernels::VariantKey { msaa }))?;
        let pipeline = |entry| program.compute_pipeline(gpu.device(), entry);
        let params = gpu.device().create_buffer(&wgpu::BufferDescriptor {
            label: Some("compute raster params"),
            size: size_of::<kernels::RasterParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Ok(Self {
            triangles: pipeline("raster_triangles")?,
            args: pipeline("tile_args")?,
            late_args: pipeline("late_triangle_args")?,
            tiles: pipeline("raster_tiles")?,
            program,
            params,
            msaa: config.msaa,
            small_area: DEFAULT_SMALL_AREA,
            every_slot: !culled,
            buffers: Arc::default(),
        })
    }

    /// Triangles whose pixel box covers at most `pixels` are rasterised by one invocation,
    /// larger ones by 16×16 tiles (0: every triangle by tiles).
    pub fn with_small_area(mut self, pixels: u32) -> Self {
        self.small_area = pixels;
        self
    }

    /// The triangle ID every sample of the last frame holds (0: none), `(y × width + x) ×
    /// msaa + s`. Blocks until the GPU is done: for tests and tools.
    pub fn read_ids(&self, gpu: &GpuContext) -> Result<Vec<u32>, GpuError> {
        let Some(vis64) = self.buffer(|b| b.vis64.clone()) else {
            return Ok(Vec::new());
        };
        let words: Vec<u32> = crate::readback::read_buffer(gpu.device(), gpu.queue(), &vis64)?;
        Ok(words
            .chunks_exact(2)
            .map(|w| if w[1] == 0 { 0 } else { !w[0] })
            .collect())
    }

    /// What the last frame counted (its last half, under occlusion culling). Blocks until the
    /// GPU is done: for tests and tools.
    pub fn read_counts(&self, gpu: &GpuContext) -> Result<ComputeRasterCounts, GpuError> {
        let Some(counters) = self.buffer(|b| b.counters.clone()) else {
            return Ok(ComputeRasterCounts::default());
        };
        let c: Vec<u32> = crate::readback::read_buffer(gpu.device(), gpu.queue(), &counters)?;
        Ok(ComputeRasterCounts {
            large: c[kernels::LARGE_COUNT as usize],
            tiles: c[kernels::ITEM_COUNT as usize],
            overflow: c[kernels::OVERFLOW as usize],
        })
    }

    fn buffer<T>(&self, f: impl FnOnce(&Buffers) -> T) -> Option<T> {
        let buffers = self.buffers.lock().unwrap_or_else(PoisonError::into_inner);
        buffers.as_ref().map(f)
    }
}

/// Each draw's class for `layout`: the opaque batches' draws, with their batch's face culling
/// and winding, and their slot; 0 for masked, blended and hidden draws. And the chunks of the
/// triangles of the draws with a class (`triangles` a draw), in draw order: `(draw, first
/// triangle)`.
fn classes_and_chunks(layout: &BatchLayout, triangles: &[u32]) -> (Vec<u32>, Vec<[u32; 2]>) {
    let mut out = vec![0u32; triangles.len().max(1)];
    for batch in layout.batches.iter().filter(|b| !b.masked) {
        let class = kernels::RASTERISE
            | if batch.double_sided {
                kernels::DOUBLE_SIDED
            } else {
                0
            }
            | if batch.mirrored { kernels::MIRRORED } else { 0 };
        let slots = batch.first_slot..batch.first_slot + batch.slot_count;
        for slot in slots {
            let draw = layout.slot_draws[slot as usize];
            if draw != NO_DRAW
                && let Some(c) = out.get_mut(draw as usize)
            {
                *c = class | slot << kernels::SLOT_SHIFT;
            }
        }
    }
    let chunks = (0u32..)
        .zip(triangles)
        .filter(|&(draw, _)| out[draw as usize] != 0)
        .flat_map(|(draw, &count)| {
            (0..count)
                .step_by(kernels::TRIANGLE_WORKGROUP as usize)
                .map(move |first| [draw, first])
        })
        .collect();
    (out, chunks)
}

impl ComputeRasterPass {
    /// Group 0 over `b`, the half's slot arguments and occlusion culling's counters of slots
    /// drawn (`drawn`), after writing this frame's parameters (the same for both halves).
    fn group0(
        &self,
        frame: &FrameInputs,
        (b, slot_args, drawn): (&Buffers, &wgpu::Buffer, &wgpu::Buffer),
    ) -> Result<wgpu::BindGroup, RenderError> {
        let (c, s) = (&frame.config, b.sizing);
        let params = kernels::RasterParams::new(
            c.width,
            c.height,
            b.chunk_count,
            self.small_area,
            s.large_capacity,
            s.item_capacity,
            u32::from(self.every_slot),
            0,
        );
        frame
            .gpu
            .queue()
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let group0 = kernels::Group0 {
            camera: frame.camera_uniform.buffer.as_entire_buffer_binding(),
            params: self.params.as_entire_buffer_binding(),
            classes: b.classes.as_entire_buffer_binding(),
            vis64: b.vis64.as_entire_buffer_binding(),
            counters: b.counters.as_entire_buffer_binding(),
            large: b.large.as_entire_buffer_binding(),
            items: b.items.as_entire_buffer_binding(),
            tile_args: b.tile_args.as_entire_buffer_binding(),
            slot_args: slot_args.as_entire_buffer_binding(),
            chunks: b.chunks.as_entire_buffer_binding(),
            drawn: drawn.as_entire_buffer_binding(),
        };
        Ok(self.program.bind_group(
            frame.gpu.device(),
            kernels::Group0::GROUP,
            &shader_bind::Resources::of(&group0),
            "compute raster",
        )?)
    }
}

impl ComputeRasterPass {
    /// Adds the compute raster of `half` to `graph` for `list`'s batches (the slots it keeps,
    /// unless the pass rasterises every draw), whose draws' geometry records are
    /// `draw_geometry`; returns the samples buffer, written (imported by
    /// the first half: the graph keeps the pass), and its handle after the write.
    pub(crate) fn add_raster(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
        (list, draw_geometry): (&SceneDrawList, &wgpu::Buffer),
        half: RasterHalf,
    ) -> Result<(wgpu::Buffer, Handle<Buffer>), RenderError> {
        let device = frame.gpu.device();
        let sizing = Sizing::of(frame, self.msaa, self.small_area);
        sizing.check(device)?;
        let mut guard = self.buffers.lock().unwrap_or_else(PoisonError::into_inner);
        let b = match guard.take() {
            Some(b) if b.sizing == sizing => guard.insert(b),
            _ => guard.insert(Buffers::new(device, sizing)),
        };
        let revision = frame.instances.revision;
        let current = b.classes_of.as_ref().is_some_and(|(layout, kept)| {
            *kept == revision
                && layout
                    .upgrade()
                    .is_some_and(|l| Arc::ptr_eq(&l, &list.layout))
        });
        if !current {
            let triangles: Vec<u32> = (frame.instances.draws.iter())
                .map(|d| d.geometry.index_count / 3)
                .collect();
            let (classes, chunks) = classes_and_chunks(&list.layout, &triangles);
            let queue = frame.gpu.queue();
            queue.write_buffer(&b.classes, 0, bytemuck::cast_slice(&classes));
            if !chunks.is_empty() {
                queue.write_buffer(&b.chunks, 0, bytemuck::cast_slice(&chunks));
            }
            b.chunk_count = chunks.len() as u32;
            b.classes_of = Some((Arc::downgrade(&list.layout), revision));
        }
        // The late half dispatches its triangles only where occlusion culling's second phase
        // drew a slot the first did not; elsewhere `DRAWN` is unread.
        let drawn = match half {
            RasterHalf::Late(_) => list.occlusion.as_ref().map(|o| &o.visible),
            RasterHalf::First => None,
        };
        let recording = Arc::new(Recording {
            pipelines: [
                self.triangles.clone(),
                self.args.clone(),
                self.tiles.clone(),
                self.late_args.clone(),
            ],
            groups: [
                self.group0(
                    frame,
                    (b, &list.slot_args, drawn.unwrap_or(&list.slot_args)),
                )?,
                frame.instances.draw_group_for(device, &self.program)?,
                geometry_group(device, &self.program, &frame.scene, draw_geometry)?,
            ],
            vis64: b.vis64.clone(),
            counters: b.counters.clone(),
            tile_args: b.tile_args.clone(),
            indirect: b.indirect.clone(),
            chunks: b.chunk_count,
            clear_samples: matches!(half, RasterHalf::First),
            late_dispatch: drawn.is_some(),
        });
        let vis64 = b.vis64.clone();
        drop(guard);
        let (mut handle, names) = match half {
            RasterHalf::First => {
                let handle = resources.import_buffer(
                    graph,
                    "compute raster samples",
                    &vis64,
                    ImportAccess::ReadWrite,
                );
                (handle, [self.name(), TILES_PASS])
            }
            RasterHalf::Late(handle) => (handle, [LATE_PASS, LATE_TILES_PASS]),
        };
        // Two graph passes, so a frame's timings show the triangles and the tiles apart. They
        // read the list's arguments so that culling writes them first.
        let tiles = Arc::clone(&recording);
        graph
            .add_pass(names[0])
            .read_buffer(list.args, BufferAccess::Indirect)
            .write_buffer(&mut handle, BufferAccess::StorageWrite)
            .execute(move |ctx| recording.record_triangles(ctx));
        graph
            .add_pass(names[1])
            .write_buffer(&mut handle, BufferAccess::StorageWrite)
            .execute(move |ctx| tiles.record_tiles(ctx));
        Ok((vis64, handle))
    }
}

impl Pass for ComputeRasterPass {
    fn name(&self) -> &'static str {
        "compute raster"
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let missing = |input| {
            RenderError::Config(ConfigError::MissingInput {
                pass: "compute raster",
                input,
            })
        };
        let vis = resources
            .visibility
            .clone()
            .ok_or(missing("the visibility raster's draw geometry"))?;
        let list = resources
            .scene_draws
            .clone()
            .ok_or(missing("the scene's draw batches (scene culling)"))?;
        // The samples are imported read-write, so the graph keeps the pass though nothing in
        // the frame reads them.
        self.add_raster(
            graph,
            frame,
            resources,
            (&list, &vis.draw_geometry),
            RasterHalf::First,
        )?;
        Ok(())
    }
}

/// What one frame of the pass records with.
struct Recording {
    /// `raster_triangles`, `tile_args`, `raster_tiles`, `late_triangle_args`.
    pipelines: [wgpu::ComputePipeline; 4],
    /// Groups 0, 1 and 3 (the module binds nothing at 2).
    groups: [wgpu::BindGroup; 3],
    vis64: wgpu::Buffer,
    counters: wgpu::Buffer,
    tile_args: wgpu::Buffer,
    indirect: wgpu::Buffer,
    /// `raster_triangles`' workgroups.
    chunks: u32,
    /// Whether the samples are cleared first (the first half).
    clear_samples: bool,
    /// Whether the triangles are dispatched from `late_triangle_args` (the late half).
    late_dispatch: bool,
}

impl Recording {
    /// Clears the samples and counters, rasterises the triangles and lists the large ones'
    /// tiles, and writes the tiles' dispatch.
    fn record_triangles(&self, ctx: &mut PassContext<'_>) {
        if self.clear_samples {
            ctx.encoder.clear_buffer(&self.vis64, 0, None);
        }
        ctx.encoder.clear_buffer(&self.counters, 0, None);
        let [triangles, args, _, late_args] = &self.pipelines;
        // `TILE_ARGS` is bound read-write to every entry point: a dispatch reads a copy.
        let late = u64::from(kernels::LATE_ARGS) * 4;
        if self.late_dispatch {
            {
                let mut pass = self.begin(ctx, "compute raster late dispatch");
                pass.set_pipeline(late_args);
                pass.dispatch_workgroups(1, 1, 1);
            }
            ctx.encoder.copy_buffer_to_buffer(
                &self.tile_args,
                late,
                &self.indirect,
                late,
                Some(12),
            );
        }
        {
            let mut pass = self.begin(ctx, "compute raster");
            pass.set_pipeline(triangles);
            if self.late_dispatch {
                pass.dispatch_workgroups_indirect(&self.indirect, late);
            } else {
                pass.dispatch_workgroups(
                    self.chunks.min(kernels::TILE_ROW),
                    self.chunks.div_ceil(kernels::TILE_ROW),
                    1,
                );
            }
            pass.set_pipeline(args);
            pass.dispatch_workgroups(1, 1, 1);
        }
        ctx.encoder
            .copy_buffer_to_buffer(&self.tile_args, 0, &self.indirect, 0, Some(12));
    }

    /// Rasterises the large triangles' tiles.
    fn record_tiles(&self, ctx: &mut PassContext<'_>) {
        let [_, _, tiles, _] = &self.pipelines;
        let mut pass = self.begin(ctx, TILES_PASS);
        pass.set_pipeline(tiles);
        pass.dispatch_workgroups_indirect(&self.indirect, 0);
    }

    /// A compute pass with every group bound.
    fn begin<'a>(
        &self,
        ctx: &'a mut PassContext<'_>,
        label: &str,
    ) -> TimedPass<'a, wgpu::ComputePass<'a>> {
        let mut pass = ctx.encoder.begin_compute(label);
        for (index, g) in [0, 1, 3].into_iter().zip(&self.groups) {
            pass.set_bind_group(index, g, &[]);
        }
        pass
    }
}
