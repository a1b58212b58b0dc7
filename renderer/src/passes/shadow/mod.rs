//! The shadow-atlas pass: every shadowed light's depth in one atlas, at a resolution chosen per
//! light and frame, with static casters cached and only what changed redrawn.
//!
//! Each frame, `prepare` plans on the CPU ([`crate::shadow::frame::ShadowPlanner`]: requests,
//! allocation, views, cache decisions), uploads the view records shading reads
//! (`shadow_atlas::SHADOW_VIEWS`) and the casters' clip matrices, and writes the `shadow` index
//! of every light whose shadow changed into the light buffers. `add_to_graph` publishes the atlas
//! for shading ([`FrameResources::shadows`]) and adds a graph node only when some region needs
//! a draw or a copy: a frame where nothing changed runs no shadow work at all.

mod casters;
mod culling;
mod gpu;
mod record;
mod slots;
mod view;
mod work;

#[cfg(any(test, feature = "internals"))]
pub use gpu::SHADOW_FORMAT;
pub use view::ShadowAtlasViewPass;

use std::sync::Arc;

use crate::frame_data::ConfigError;

use shaders_gen::forward::forward;
use shaders_gen::shadow::shadow_caster;

use super::Pass;
use crate::frame_data::{
    FrameInputs, FrameReport, FrameResources, LightSet, RenderError, RendererConfig,
    ShadowResources,
};
use crate::graph::{ImportAccess, RenderGraph, TextureAccess};
use crate::scene::Aabb;
use crate::shadow::ShadowReport;
use crate::shadow::cache::CasterChanges;
use crate::shadow::frame::{FramePlan, PlanInputs, ShadowPlanner, ViewRecord};
use casters::CasterCache;
use culling::CasterCulling;
use gpu::{ShadowPipelines, ShadowTargets};
use record::{CastSource, Recording};
use shaders_gen::shared::shadow_atlas::NO_SHADOW;
use work::{CastList, WorkItem, work_items};

/// The shadow pass.
#[derive(Debug)]
pub struct ShadowPass {
    /// The configuration's shadow settings fitted to its output when the pass was made
    /// ([`RendererConfig::fitted_shadows`]); a resize that changes them rebuilds the pass.
    settings: crate::shadow::ShadowConfig,
    pipelines: ShadowPipelines,
    targets: ShadowTargets,
    planner: ShadowPlanner,
    plan: FramePlan,
    /// The light set whose `shadow` indices the buffers hold, and those indices.
    written: Option<(Arc<LightSet>, Vec<u32>, Vec<u32>)>,
    /// The view records in the views buffer.
    uploaded: Vec<forward::ShadowView>,
    /// This frame's work items, and their casts where the CPU lists them.
    items: Vec<WorkItem>,
    listed: Option<Arc<CastList>>,
    /// Casters culled per region on the GPU (their casts buffer serves the CPU lists too).
    culling: CasterCulling,
    /// Whether the device draws indirectly with a first instance (else the CPU lists casts).
    indirect: bool,
    /// Group 0 of the caster pipelines, with the view and cast buffers it binds.
    caster_group: Option<(wgpu::Buffer, wgpu::Buffer, wgpu::BindGroup)>,
    /// The last frame's report, and whether the GPU counted its casts.
    last_report: Option<(ShadowReport, bool)>,
    /// The casters of the scene and instances they were built from, followed through the
    /// instance table's change log, so a frame where nothing moved does not walk the scene's
    /// draws.
    casters: Option<CasterCache>,
    /// Whether the shadow cache's last plan was made with `casters` (a plan without shadowed
    /// lights is made with none): only then can it be told which casters changed since.
    planned_with_casters: bool,
}

impl ShadowPass {
    /// The pass for `config.shadows` fitted to the output; its atlas size must fit the device.
    pub fn new(gpu: &crate::GpuContext, config: &RendererConfig) -> Result<Self, RenderError> {
        let settings = config.fitted_shadows();
        let s = &settings;
        let max = gpu.device().limits().max_texture_dimension_2d;
        let min = s
            .min_resolution
            .max(s.cascade_resolution.min(s.max_resolution));
        if s.enabled && !(min..=max).contains(&s.atlas_size) {
            return Err(RenderError::Config(ConfigError::ShadowAtlasSize {
                asked: s.atlas_size,
                min,
                max,
            }));
        }
        let pipelines = ShadowPipelines::new(gpu)?;
        let size = if s.enabled { s.atlas_size } else { 1 };
        let targets = ShadowTargets::new(gpu.device(), &pipelines, size, s.cache, 64)?;
        Ok(Self {
            settings,
            pipelines,
            targets,
            planner: ShadowPlanner::default(),
            plan: FramePlan::default(),
            written: None,
            uploaded: Vec::new(),
            items: Vec::new(),
            listed: None,
            culling: CasterCulling::new(gpu)?,
            indirect: (gpu.device().features()).contains(wgpu::Features::INDIRECT_FIRST_INSTANCE),
            caster_group: None,
            last_report: None,
            casters: None,
            planned_with_casters: false,
        })
    }

    /// The last frame's report, its cast count the newest that has arrived (polling first):
    /// after [`crate::frame::Renderer::finish`], the last frame's own.
    pub fn report(&mut self) -> Option<ShadowReport> {
        let (mut report, counted) = self.last_report.clone()?;
        if counted {
            self.culling.poll();
            report.cache.draws = self.culling.last_drawn.unwrap_or(0);
        }
        Some(report)
    }

    /// This frame's plan (after `prepare`).
    #[cfg(any(test, feature = "internals"))]
    pub fn plan(&self) -> &FramePlan {
        &self.plan
    }

    /// Writes the view records and the casters' matrices of the plan.
    fn upload_views(&mut self, frame: &FrameInputs) {
        let views = &self.plan.views;
        if views.len() > self.targets.capacity {
            let capacity = views.len().next_power_of_two();
            self.targets.grow(frame.gpu.device(), capacity);
            // New buffers hold nothing yet.
            self.uploaded.clear();
        }
        if views.is_empty() {
            return;
        }
        let records: Vec<forward::ShadowView> = views.iter().map(view_record).collect();
        // A frame whose views did not change (every region cached) uploads nothing.
        if bytemuck::cast_slice::<_, u8>(&records) == bytemuck::cast_slice::<_, u8>(&self.uploaded)
        {
            return;
        }
        let casters: Vec<shadow_caster::CasterView> = views
            .iter()
            .map(|v| shadow_caster::CasterView::new(v.view.clip_from_world))
            .collect();
        let queue = frame.gpu.queue();
        queue.write_buffer(&self.targets.views, 0, bytemuck::cast_slice(&records));
        queue.write_buffer(
            &self.targets.caster_views,
            0,
            bytemuck::cast_slice(&casters),
        );
        self.uploaded = records;
    }

    /// This frame's work items and what draws their casters: the GPU culling's buffers
    /// brought to the scene and the work written, or, on a device without indirect first
    /// instances, the casts listed here and written; then the caster group over the buffers.
    fn prepare_casts(
        &mut self,
        frame: &FrameInputs,
        changed: Option<&[u32]>,
        shadowed: bool,
    ) -> Result<(), RenderError> {
        self.items = work_items(&self.plan.regions);
        self.listed = None;
        let Some(casters) = self.casters.as_ref().filter(|_| shadowed) else {
            return Ok(());
        };
        let cull = frame.config.cull_draws;
        let gpu = &frame.gpu;
        if self.indirect {
            self.culling.follow(frame, casters, changed);
            (self.culling).prepare(gpu, &self.items, &self.plan.regions, cull)?;
        } else {
            let list = CastList::new(&self.items, &self.plan.regions, &casters.casters, cull);
            self.culling.write_casts(gpu, &list.casts);
            self.listed = Some(Arc::new(list));
        }
        let (views, casts) = (&self.targets.caster_views, self.culling.casts());
        let current =
            (self.caster_group.as_ref()).is_some_and(|(v, c, _)| v == views && c == casts);
        if !current {
            let group = self.pipelines.caster_group(gpu.device(), views, casts)?;
            self.caster_group = Some((views.clone(), casts.clone(), group));
        }
        Ok(())
    }

    /// Writes the `shadow` field of every light whose first view changed.
    fn write_light_indices(&mut self, frame: &FrameInputs) {
        let index = |s: &Option<u32>| s.unwrap_or(NO_SHADOW);
        let punctual: Vec<u32> = self.plan.punctual_shadow.iter().map(index).collect();
        let directional: Vec<u32> = self.plan.directional_shadow.iter().map(index).collect();
        let (old_p, old_d) = match self.written.take() {
            Some((set, p, d)) if Arc::ptr_eq(&set, &frame.lights) => (p, d),
            // A new light set starts with every light at NO_SHADOW.
            _ => (
                vec![NO_SHADOW; punctual.len()],
                vec![NO_SHADOW; directional.len()],
            ),
        };
        let queue = frame.gpu.queue();
        let field = std::mem::offset_of!(forward::GpuLight, shadow) as u64;
        let stride = size_of::<forward::GpuLight>() as u64;
        let buffers = [
            (&frame.lights.punctual_buffer, &punctual, &old_p),
            (&frame.lights.directional_buffer, &directional, &old_d),
        ];
        for (buffer, new, old) in buffers {
            for (i, (n, o)) in new.iter().zip(old.iter()).enumerate() {
                if n != o {
                    let at = i as u64 * stride + field;
                    queue.write_buffer(buffer, at, bytemuck::bytes_of(n));
                }
            }
        }
        self.written = Some((Arc::clone(&frame.lights), punctual, directional));
    }
}

/// The GPU record of a view.
fn view_record(v: &ViewRecord) -> forward::ShadowView {
    forward::ShadowView::new(
        v.view.clip_from_world,
        v.rect_uv,
        v.view.texel_world,
        u32::from(v.view.orthographic),
        v.view.split_far,
        v.faces,
    )
}

impl Pass for ShadowPass {
    fn name(&self) -> &'static str {
        "shadow atlas"
    }

    fn prepare(&mut self, frame: &FrameInputs) -> Result<(), RenderError> {
        let config = &self.settings;
        if !config.enabled {
            self.plan = FramePlan::default();
            return Ok(());
        }
        let started = web_time::Instant::now();
        let lights = &frame.lights;
        let shadowed = lights
            .punctual_sources
            .iter()
            .chain(&lights.directional_sources)
            .any(|l| l.casts_shadow);
        // Without a light that casts a shadow the plan has no region: no caster is needed, and
        // the scene's draws are not walked.
        let changed = match (&mut self.casters, shadowed) {
            (Some(c), true) => c.follow(frame),
            (None, true) => {
                self.casters = Some(CasterCache::new(frame));
                None
            }
            (_, false) => None,
        };
        let caster_changes = match &changed {
            Some(list) if self.planned_with_casters => CasterChanges::Only(list),
            _ => CasterChanges::Unknown,
        };
        self.planned_with_casters = shadowed;
        let (casters, scene_bounds) = match &self.casters {
            Some(c) if shadowed => (c.casters.as_slice(), c.bounds),
            _ => (&[][..], Aabb::EMPTY),
        };
        let inputs = PlanInputs {
            config,
            punctual: &frame.lights.punctual_sources,
            directional: &frame.lights.directional_sources,
            camera_view: frame.camera.view,
            camera_projection: frame.camera.projection,
            camera_near: frame.camera.near,
            viewport_height: frame.config.height as f32,
            scene_bounds,
            casters,
            caster_changes,
        };
        self.plan = self.planner.plan(&inputs);
        self.upload_views(frame);
        self.prepare_casts(frame, changed.as_deref(), shadowed)?;
        self.write_light_indices(frame);
        self.plan.report.cpu_plan_ms = started.elapsed().as_secs_f64() * 1e3;
        Ok(())
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let t = &self.targets;
        let mut atlas =
            resources.import_texture(graph, "shadow atlas", &t.atlas, ImportAccess::ReadWrite);
        if let (false, Some((.., caster_group))) = (self.items.is_empty(), &self.caster_group) {
            let casts = match &self.listed {
                Some(list) => CastSource::Listed(Arc::clone(list)),
                None => CastSource::Culled {
                    dispatches: self.culling.dispatches(),
                    args: self.culling.args().clone(),
                    opaque: self.culling.layout().opaque,
                },
            };
            let recording = Recording {
                items: self.items.clone(),
                casts,
                scene: Arc::clone(&frame.scene),
                instances: Arc::clone(&frame.instances),
                caster: self.pipelines.caster.clone(),
                clear: self.pipelines.clear.clone(),
                copy: self.pipelines.copy.clone(),
                caster_group: caster_group.clone(),
                copy_group: t.copy_group.clone(),
                static_atlas: t.static_atlas.clone(),
            };
            let target = t.atlas_view.clone();
            graph
                .add_pass(self.name())
                .write_texture(&mut atlas, TextureAccess::DepthWrite)
                .execute(move |ctx| recording.record(&mut ctx.encoder, &target));
        }
        resources.shadows = Some(ShadowResources {
            atlas,
            views: t.views.clone(),
            atlas_view: t.atlas_view.clone(),
            sampler: t.sampler.clone(),
            regions: Arc::new(
                self.plan
                    .regions
                    .iter()
                    .map(|r| {
                        let (rect, light) = (r.region.rect, r.region.key.light);
                        [rect.x, rect.y, rect.side, light]
                    })
                    .collect(),
            ),
        });
        Ok(())
    }

    fn after_execute(
        &mut self,
        frame: &FrameInputs,
        _resources: &FrameResources,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        if self.listed.is_none() && !self.items.is_empty() {
            self.culling.after_execute(encoder, frame.index);
        }
    }

    fn after_submit(&mut self, _frame: &FrameInputs, report: &mut FrameReport) {
        if !self.settings.enabled {
            return;
        }
        self.culling.after_submit();
        let mut shadows = self.plan.report.clone();
        let counted = self.listed.is_none() && !self.items.is_empty();
        shadows.cache.draws = match (&self.listed, self.items.is_empty()) {
            (_, true) => 0,
            (Some(list), false) => list.casts.len() as u32,
            (None, false) => self.culling.last_drawn.unwrap_or(0),
        };
        self.last_report = Some((shadows.clone(), counted));
        report.shadows = Some(shadows);
    }
}
