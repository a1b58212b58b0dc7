//! Light culling: the tiled / 2.5D or clustered kernel over the pre-Z depth, writing the light
//! and decal lists of the grid and index list the shading passes read. It owns the culler of the configured path (built
//! on the first frame and rebuilt when the size, light count, scene or camera range call for
//! it), sizes the index list before each frame from a CPU bound of what the frame can request
//! (`sizing`), so a frame after a jump in light count or camera is exact too, and reads the
//! counters back asynchronously (an overflow, possible only past one storage binding, is
//! reported and grows the list). The naive paths have no culling pass.

mod culler;
mod sizing;

pub use culler::Culler;

use crate::frame_data::ConfigError;
use std::sync::Arc;

use super::Pass;
use crate::GpuContext;
use crate::culling::clustered::{ClusterCullConfig, ClusteredCulling};
use crate::culling::hierarchy::{CullItems, CullSphere, DepthInput};
use crate::culling::lists::CullCounters;
use crate::culling::max_index_entries;
use crate::culling::overflow::grow_for;
use crate::culling::tiled::{TileCullConfig, TiledCulling};
use crate::culling::{ClusterGrid, Method};
use crate::frame_data::{
    FrameInputs, FrameReport, FrameResources, LightListHandles, RenderError, RenderPath,
    VisibilitySamples,
};
use crate::graph::{
    Buffer, BufferAccess, Handle, ImportAccess, RenderGraph, Texture, TextureAccess,
};
use crate::readback_ring::ReadbackRing;

/// Index-list entries before the first frame; every frame grows the list to its CPU bound
/// first (`sizing`), so this only saves memory on small frames.
const INITIAL_INDEX_ENTRIES: u32 = 1 << 16;

/// Depth slices of the clustered path (the kernels' limit, `cull_append::MAX_LISTS`).
pub const CLUSTER_SLICES: u32 = 32;

/// The culling a frame needs: its path's, except that the deferred paths, which shade opaque
/// surfaces with lights they cull themselves, need tiled lists only for the other passes that
/// read lists (blended surfaces, decals in the G-buffer, particles, the heatmap views), and no
/// culling without them.
fn culling_path(frame: &FrameInputs, has_blend: bool) -> RenderPath {
    let c = &frame.config;
    if c.path == RenderPath::Visibility {
        // Its opaque shading reads the clustered lists.
        return RenderPath::Clustered;
    }
    if !c.path.is_deferred() {
        return c.path;
    }
    let heatmap = matches!(
        c.view,
        crate::frame_data::FrameView::Heatmap | crate::frame_data::FrameView::DecalHeatmap
    );
    if has_blend || frame.decals.count() > 0 || frame.particles.is_some() || heatmap {
        RenderPath::Tiled
    } else {
        RenderPath::NaivePrez
    }
}

/// The light-culling pass.
#[derive(Debug)]
pub struct LightCullPass {
    gpu: GpuContext,
    culler: Culler,
    /// On the tiled paths with particles: clustered lists over every depth slice for the
    /// particle passes (particles float where no tile list reaches).
    particle_culler: Option<Arc<ClusteredCulling>>,
    /// The size the culler was built for.
    built_for: (u32, u32),
    counters: ReadbackRing,
    index_capacity: u32,
    last_counters: Option<CullCounters>,
}

impl LightCullPass {
    pub fn new(gpu: &GpuContext) -> Self {
        Self {
            gpu: gpu.clone(),
            culler: Culler::Naive,
            particle_culler: None,
            built_for: (0, 0),
            counters: ReadbackRing::new(
                gpu.device(),
                "cull counters readback",
                2 * CullCounters::WORDS,
            ),
            index_capacity: max_index_entries(gpu.device()).min(INITIAL_INDEX_ENTRIES),
            last_counters: None,
        }
    }

    /// The culler in use (`Naive` before the first frame).
    pub fn culler(&self) -> &Culler {
        &self.culler
    }

    /// The newest culling counters that have arrived, polling first.
    pub fn counters(&mut self) -> Option<CullCounters> {
        self.poll_counters();
        self.last_counters
    }

    /// Rebuilds the culler when the frame no longer fits it.
    fn ensure_culler(&mut self, frame: &FrameInputs) -> Result<(), RenderError> {
        let c = &frame.config;
        let items = (frame.lights.spheres.len() as u32 + frame.decals.count())
            .max(1)
            .next_power_of_two();
        let has_blend = frame.scene.has_blended();
        // Skipping froxels without a depth sample is exact only when every shaded point is a
        // depth sample: no blended surfaces (absent from pre-Z) and no MSAA (an edge fragment is
        // shaded at the pixel centre, which may lie in a froxel no visible sample occupies).
        // Particles are lit in every slice in front of the surfaces, so they need every list.
        let particles = frame.particles.is_some();
        let skip_empty = !has_blend && c.msaa == 1 && !particles;
        let path = culling_path(frame, has_blend);
        let particle_lists = particles && path.is_culled() && path != RenderPath::Clustered;
        let bound =
            sizing::frame_entry_bound(frame, path, has_blend, particle_lists, CLUSTER_SLICES);
        let limit = max_index_entries(self.gpu.device());
        self.index_capacity = sizing::grown_capacity(bound, self.index_capacity, limit);
        self.ensure_particle_culler(frame, particle_lists, items)?;
        let same_size = self.built_for == (c.width, c.height);
        let ok = same_size
            && match (&self.culler, path) {
                (Culler::Tiled(t), RenderPath::Tiled | RenderPath::Depth25) => {
                    t.config.item_capacity >= items
                        && t.config.index_capacity == self.index_capacity
                        && t.config.transparent_lists == has_blend
                        && t.config.tile == c.tile
                        && t.config.msaa == c.msaa
                        && t.config.brute_force == c.cull_brute_force
                        && t.config.depth_mask == (path == RenderPath::Depth25)
                }
                (Culler::Clustered(k), RenderPath::Clustered) => {
                    self.clustered_fits(k, frame, skip_empty, items)
                }
                _ => false,
            };
        if ok {
            return Ok(());
        }
        self.built_for = (c.width, c.height);
        self.culler = match path {
            RenderPath::Naive
            | RenderPath::NaivePrez
            | RenderPath::Tbdr
            | RenderPath::TbdrPerSample
            | RenderPath::Deferred => Culler::Naive,
            RenderPath::Tiled | RenderPath::Depth25 => {
                let config = TileCullConfig {
                    tile: c.tile,
                    msaa: c.msaa,
                    depth_mask: path == RenderPath::Depth25,
                    transparent_lists: has_blend,
                    brute_force: c.cull_brute_force,
                    coarse_slots: None,
                    index_capacity: self.index_capacity,
                    item_capacity: items,
                };
                Culler::Tiled(Arc::new(TiledCulling::new(
                    &self.gpu, config, c.width, c.height,
                )?))
            }
            RenderPath::Clustered | RenderPath::Visibility => {
                Culler::Clustered(Arc::new(self.clustered(frame, skip_empty, items)?))
            }
        };
        Ok(())
    }

    /// The clustered culling settings of `frame` (32 slices over the camera's range).
    fn cluster_config(
        &self,
        frame: &FrameInputs,
        skip_empty: bool,
        items: u32,
    ) -> ClusterCullConfig {
        let c = &frame.config;
        ClusterCullConfig {
            grid: ClusterGrid {
                tile: c.tile,
                slices: CLUSTER_SLICES,
                near: frame.camera.near,
                far: frame.camera.far,
            },
            msaa: c.msaa,
            vis64: c.reads_compute_samples(),
            skip_empty,
            brute_force: c.cull_brute_force,
            coarse_slots: None,
            index_capacity: self.index_capacity,
            item_capacity: items,
        }
    }

    /// Whether clustered culler `k` serves `frame` as [`Self::cluster_config`] would build it
    /// (its item capacity at least `items`; the size is checked apart).
    fn clustered_fits(
        &self,
        k: &ClusteredCulling,
        frame: &FrameInputs,
        skip_empty: bool,
        items: u32,
    ) -> bool {
        k.config.item_capacity >= items
            && k.config == self.cluster_config(frame, skip_empty, k.config.item_capacity)
    }

    /// A clustered culler for `frame`.
    fn clustered(
        &self,
        frame: &FrameInputs,
        skip_empty: bool,
        items: u32,
    ) -> Result<ClusteredCulling, RenderError> {
        let (config, c) = (self.cluster_config(frame, skip_empty, items), &frame.config);
        Ok(ClusteredCulling::new(&self.gpu, config, c.width, c.height)?)
    }

    /// Builds, keeps or drops the particles' own clustered culler (`wanted` on the tiled paths
    /// with particles).
    fn ensure_particle_culler(
        &mut self,
        frame: &FrameInputs,
        wanted: bool,
        items: u32,
    ) -> Result<(), RenderError> {
        if !wanted {
            self.particle_culler = None;
            return Ok(());
        }
        let c = &frame.config;
        let tiles = glam::UVec2::new(c.width.div_ceil(c.tile), c.height.div_ceil(c.tile));
        let fits = self.particle_culler.as_ref().is_some_and(|k| {
            k.levels.tiles == tiles && self.clustered_fits(k, frame, false, items)
        });
        if !fits {
            self.particle_culler = Some(Arc::new(self.clustered(frame, false, items)?));
        }
        Ok(())
    }

    /// Picks up culling counters that have arrived; on overflow, warns and grows the index list
    /// for the next frame (up to one storage binding; past that the overflow stays reported).
    fn poll_counters(&mut self) {
        let Some((_, words)) = self.counters.poll(self.gpu.device()) else {
            return;
        };
        let (frame_words, particle_words) = words.split_at(CullCounters::WORDS as usize);
        let counters = CullCounters::from_words(frame_words);
        self.last_counters = Some(counters);
        // The index list both cullers share grows for whichever asked more.
        let particle = CullCounters::from_words(particle_words);
        let counters = if particle.requested_entries > counters.requested_entries {
            particle
        } else {
            counters
        };
        if counters.dropped == 0 {
            return;
        }
        let limit = max_index_entries(self.gpu.device());
        let grown = grow_for(&counters, self.index_capacity)
            .map(|index| index.min(limit))
            .filter(|&index| index > self.index_capacity);
        log::warn!(
            "light culling dropped {} list entries: {} entries were requested of an index list of \
             {}; {}",
            counters.dropped,
            counters.requested_entries,
            self.index_capacity,
            if grown.is_some() {
                "growing the index list for the next frame"
            } else {
                "the index list is as large as one storage binding: use the 2.5D or clustered \
                 path, smaller light radii or fewer lights"
            }
        );
        if let Some(index) = grown {
            self.index_capacity = index;
        }
    }
}

impl LightCullPass {
    /// The particles' own clustered culling on a tiled path, as a graph pass of its own.
    fn add_particle_culling(
        &self,
        graph: &mut RenderGraph,
        resources: &mut FrameResources,
        culler: &Arc<ClusteredCulling>,
        depth: Handle<Texture>,
    ) -> LightListHandles {
        let lists = &culler.levels.lists;
        let mut grid = resources.import_buffer(
            graph,
            "particle light grid",
            &lists.grid,
            ImportAccess::ReadWrite,
        );
        let mut indices = resources.import_buffer(
            graph,
            "particle light indices",
            &lists.indices,
            ImportAccess::ReadWrite,
        );
        let k = Arc::clone(culler);
        graph
            .add_pass("particle light culling")
            .read_texture(depth, TextureAccess::Sampled)
            .write_buffer(&mut grid, BufferAccess::StorageWrite)
            .write_buffer(&mut indices, BufferAccess::StorageWrite)
            .execute(move |ctx| {
                let view = ctx.texture(depth).create_view(&Default::default());
                let encoded = k.levels.encode(
                    ctx.device,
                    &mut ctx.encoder,
                    DepthInput::Texture(&view),
                    false,
                );
                ctx.bind(encoded);
            });
        LightListHandles {
            grid,
            indices,
            method: Method::Clustered {
                grid: culler.config.grid,
                skip_empty: false,
            },
            grid_buffer: lists.grid.clone(),
        }
    }
}

impl Pass for LightCullPass {
    fn name(&self) -> &'static str {
        "light culling"
    }

    fn prepare(&mut self, frame: &FrameInputs) -> Result<(), RenderError> {
        self.ensure_culler(frame)?;
        let (camera, gpu) = (&frame.camera, &frame.gpu);
        // Both kernels take the `CullSphere` and `CullBox` of the shared `cull_append` library.
        let spheres: Vec<CullSphere> = frame
            .lights
            .spheres
            .iter()
            .map(|s| CullSphere::new(s.center, s.radius))
            .collect();
        let items = CullItems {
            lights: &spheres,
            decals: &frame.decals.boxes,
        };
        let (view, projection, screen) = (camera.view, camera.projection, frame.screen());
        match &self.culler {
            Culler::Tiled(t) => t.upload(gpu, view, projection, screen, items)?,
            Culler::Clustered(k) => k.upload(gpu, view, projection, screen, items)?,
            Culler::Naive => {}
        }
        if let Some(k) = &self.particle_culler {
            k.upload(gpu, view, projection, screen, items)?;
        }
        Ok(())
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let (Some(lists), Some(method)) = (self.culler.lists(), self.culler.method()) else {
            return Ok(());
        };
        let missing = |input| {
            RenderError::Config(ConfigError::MissingInput {
                pass: "light culling",
                input,
            })
        };
        // Under the compute rasteriser the depths are its samples: the depth target, which
        // the light culling would otherwise make the frame resolve, stays unwritten.
        let source = if self.culler.reads_samples() {
            match resources.visibility.as_ref().map(|v| v.samples) {
                Some(VisibilitySamples::Buffer { samples }) => Source::Samples(samples),
                _ => return Err(missing("the compute rasteriser's samples")),
            }
        } else {
            Source::Texture(resources.depth.ok_or(missing("depth buffer"))?)
        };
        let mut grid =
            resources.import_buffer(graph, "light grid", &lists.grid, ImportAccess::ReadWrite);
        let mut indices = resources.import_buffer(
            graph,
            "light indices",
            &lists.indices,
            ImportAccess::ReadWrite,
        );
        let culler = self.culler.clone();
        let timed = frame.config.time_cull_dispatches;
        let mut pass = graph.add_pass(self.name());
        match source {
            Source::Texture(depth) => pass.read_texture(depth, TextureAccess::Sampled),
            Source::Samples(samples) => pass.read_buffer(samples, BufferAccess::StorageRead),
        };
        pass.write_buffer(&mut grid, BufferAccess::StorageWrite)
            .write_buffer(&mut indices, BufferAccess::StorageWrite)
            .execute(move |ctx| {
                let Some(levels) = culler.levels() else {
                    return;
                };
                let encoded = match source {
                    Source::Texture(depth) => {
                        let view = ctx.texture(depth).create_view(&Default::default());
                        levels.encode(
                            ctx.device,
                            &mut ctx.encoder,
                            DepthInput::Texture(&view),
                            timed,
                        )
                    }
                    Source::Samples(samples) => {
                        let buffer = ctx.buffer(samples).clone();
                        levels.encode(
                            ctx.device,
                            &mut ctx.encoder,
                            DepthInput::Samples(&buffer),
                            timed,
                        )
                    }
                };
                ctx.bind(encoded);
            });
        let handles = LightListHandles {
            grid,
            indices,
            method,
            grid_buffer: lists.grid.clone(),
        };
        if frame.particles.is_some() {
            resources.particle_lists = match &self.particle_culler {
                Some(k) => {
                    let depth = resources.depth.ok_or(missing("depth buffer"))?;
                    Some(self.add_particle_culling(graph, resources, k, depth))
                }
                None => Some(handles.clone()),
            };
        }
        resources.light_lists = Some(handles);
        Ok(())
    }

    fn after_execute(
        &mut self,
        frame: &FrameInputs,
        _resources: &FrameResources,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        // The frame's counters, then the particle culler's (the frame's again without one).
        if let Some(l) = self.culler.lists() {
            let particle = self
                .particle_culler
                .as_ref()
                .map_or(&l.counters, |k| &k.levels.lists.counters);
            let bytes = CullCounters::WORDS * 4;
            self.counters.record(
                encoder,
                &[(&l.counters, bytes), (particle, bytes)],
                frame.index,
            );
        }
    }

    fn after_submit(&mut self, _frame: &FrameInputs, report: &mut FrameReport) {
        self.counters.after_submit();
        self.poll_counters();
        report.culling = self.last_counters;
    }
}

/// Where this frame's light culling reads the depths.
#[derive(Clone, Copy)]
enum Source {
    /// The depth buffer.
    Texture(Handle<Texture>),
    /// The compute rasteriser's samples (a culler built with `vis64`).
    Samples(Handle<Buffer>),
}
