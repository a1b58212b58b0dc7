//! The engine-facing renderer: a device, a scene, lights and a camera in; a frame, per-pass GPU
//! timings and the compiled graph out.
//!
//! `frame` is a thin orchestrator. For the configured path it holds an ordered list of passes
//! ([`crate::passes::Pass`], chosen in `pass_list`); each frame it asks every pass to prepare and
//! to add itself to a [`RenderGraph`], then compiles it (reusing the last plan while the
//! graph's shape holds), records and submits it. It knows no
//! pass's internals. The renderer never creates a window: the caller owns the target texture.
//!
//! ```no_run
//! use glam::Vec3;
//! use renderer::frame::{RenderPath, Renderer, RendererConfig, framing_camera};
//! use renderer::scene::{LightKind, Scene, SceneLight};
//! use renderer::{GpuContext, GpuOptions};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // An engine would use GpuContext::from_parts(instance, adapter, device, queue).
//! let gpu = GpuContext::new_blocking(&GpuOptions::from_env())?;
//! let config = RendererConfig { width: 1280, height: 720, msaa: 4, path: RenderPath::Clustered, ..Default::default() };
//! let mut renderer = Renderer::new(&gpu, config)?;
//!
//! let scene = Scene::load("scene.glb")?;
//! renderer.prepare_scene(&scene)?;
//! let mut lights = scene.lights.clone();
//! lights.push(SceneLight {
//!     kind: LightKind::Point,
//!     position: scene.bounds.center() + Vec3::Y,
//!     direction: Vec3::NEG_Z,
//!     color: Vec3::ONE,
//!     intensity: 50.0,
//!     range: Some(10.0),
//!     casts_shadow: true,
//! });
//! renderer.set_lights(&lights)?;
//!
//! // The engine's own target: any texture of `config.output_format` with RENDER_ATTACHMENT,
//! // and COPY_DST for the compute tonemap; or, for an sRGB format, one stored as its linear
//! // twin with STORAGE_BINDING and the sRGB format among its view formats, which the compute
//! // tonemap writes without a copy (this helper makes one of the configured size).
//! let target = renderer::frame::create_target(gpu.device(), &config);
//! let camera = framing_camera(scene.bounds, 1280.0 / 720.0);
//! let report = renderer.render(&camera, &target)?;
//! if let Some(timings) = report.timings {
//!     for pass in timings {
//!         println!("{}: {:.3} ms", pass.pass, pass.gpu_ms);
//!     }
//! }
//! if let Some(culling) = report.culling {
//!     assert_eq!(culling.dropped, 0, "grow the lists or use smaller tiles");
//! }
//! # Ok(())
//! # }
//! ```

mod access;
mod assets;
mod cameras;
pub mod capture;
mod extra_view;
mod motion;
mod pass_list;
mod reconfigure;
mod timing;
mod views;

use std::collections::VecDeque;
use std::sync::Arc;
use web_time::Instant;

pub use crate::frame_data::{
    Ambient, ConfigError, DecalUpload, DeviceError, DrawItem, FrameCamera, FrameReport, FrameView,
    InputError, InstanceHandle, InstanceState, ParticleLighting, ParticleReport, PreparedScene,
    RenderError, RenderPath, RendererConfig, SceneDrawReport, ViewId, ViewTarget, VisibilityRaster,
};
pub use crate::passes::light_cull::Culler;
pub use assets::GeometryUsage;
pub use cameras::{
    FRAMING_YFOV_DEGREES, camera_of, create_target, default_camera, framing_camera, scene_camera,
};

use crate::GpuContext;
use crate::decals::{DecalAtlasConfig, DecalSet};
use crate::frame_data::{
    CameraUniform, FrameInputs, FrameResources, GpuDecals, InstanceTable, LightSet, ParticleInput,
    with_effective_ranges,
};
use crate::graph::{GraphCache, ImportAccess, PassTiming, RenderGraph, TextureDesc, TransientPool};
use crate::materials::MaterialProgram;
use crate::particles::ParticleSystem;
use crate::passes::Pass;
use crate::passes::particles::ParticleSimulation;
use crate::passes::shadow::ShadowPass;
use crate::scene::{Scene, SceneLight};

/// Submissions the renderer remembers for `wait_for_frames_in_flight`.
const MAX_TRACKED_FRAMES: usize = 8;

/// The culler reported when the frame has no light-culling pass.
pub(crate) static NO_CULLER: Culler = Culler::Naive;

/// The renderer.
pub struct Renderer {
    gpu: GpuContext,
    config: RendererConfig,
    passes: Vec<Box<dyn Pass>>,
    /// The material programs registered ([`Renderer::register_material`]), which the forward
    /// and G-buffer passes build pipelines for.
    materials: Vec<MaterialProgram>,
    /// Further views, drawn with the main view by [`Renderer::render_views`].
    views: Vec<extra_view::ExtraView>,
    /// The scene, and its instances (edited by handle in `motion`).
    scene: Option<(Arc<PreparedScene>, Arc<InstanceTable>)>,
    lights: Arc<LightSet>,
    /// The lights as last given to [`Renderer::set_lights`] (before effective ranges), so a
    /// change of exposure or cutoff can range them again.
    light_sources: Vec<SceneLight>,
    decals: Arc<GpuDecals>,
    particles: Option<ParticleInput>,
    camera_uniform: CameraUniform,
    pool: TransientPool,
    /// The last compiled graph's shape and plan, reused while the shape holds.
    graph_cache: GraphCache,
    profiler: wgpu_profiler::GpuProfiler,
    frame_index: u64,
    /// Submissions of frames that may still run on the GPU, oldest first.
    in_flight: VecDeque<wgpu::SubmissionIndex>,
    /// Probe stride of a capture asked for the next frame.
    capture_request: Option<u32>,
}

impl std::fmt::Debug for Renderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Renderer")
            .field("config", &self.config)
            .field("passes", &self.pass_names())
            .field("lights", &self.lights.punctual.len())
            .field("directional", &self.lights.directional.len())
            .field("decals", &self.decals.count())
            .finish_non_exhaustive()
    }
}

impl Renderer {
    /// A renderer of `config` on `gpu`, with no scene, lights, decals or particles yet. The
    /// configuration is checked against the device ([`ConfigError::SampleCount`](crate::frame::ConfigError::SampleCount),
    /// [`ConfigError::NoSubgroup`](crate::frame::ConfigError::NoSubgroup), [`ConfigError::FrameSize`](crate::frame::ConfigError::FrameSize), ...), and every program it
    /// needs is built now. [`Renderer::reconfigure`] changes it later, keeping the scene.
    pub fn new(gpu: &GpuContext, config: RendererConfig) -> Result<Self, RenderError> {
        let config = check_config(gpu, config)?;
        Ok(Self {
            passes: pass_list::passes_for(gpu, &config, &[])?,
            materials: Vec::new(),
            views: Vec::new(),
            gpu: gpu.clone(),
            config,
            scene: None,
            lights: Arc::new(LightSet::new(gpu.device(), &[])),
            light_sources: vec![],
            decals: Arc::new(GpuDecals::empty(gpu.device(), gpu.queue())),
            particles: None,
            camera_uniform: CameraUniform::new(gpu.device()),
            pool: TransientPool::new(),
            graph_cache: GraphCache::new(),
            profiler: Self::new_profiler(gpu.device())?,
            frame_index: 0,
            in_flight: VecDeque::new(),
            capture_request: None,
        })
    }

    /// The configuration in use: the one it was created with, or the last one given to
    /// [`Renderer::reconfigure`], with its choices for the device made
    /// ([`VisibilityRaster::Auto`](crate::frame::VisibilityRaster::Auto) is never here).
    pub fn config(&self) -> &RendererConfig {
        &self.config
    }

    /// The newest frame's graph in Graphviz DOT (passes in order, culled ones dashed, resources
    /// with their pool slots), drawn now from the compiled plan it kept; `None` before the
    /// first frame.
    pub fn graph_dot(&self) -> Option<String> {
        self.graph_cache.to_dot()
    }

    /// Uploads a scene; it replaces the previous one. A scene that is inconsistent or does not
    /// fit the device's limits ([`Scene::check_for_device`]), or whose materials name a material
    /// program not registered ([`Renderer::register_material`]), is an error, and the previous
    /// scene stays.
    pub fn prepare_scene(&mut self, scene: &Scene) -> Result<(), RenderError> {
        scene.check_for_device(&self.gpu.device().limits())?;
        for material in &scene.materials {
            crate::materials::check_material(material, &self.materials)?;
        }
        let prepared = PreparedScene::new(self.gpu.device(), self.gpu.queue(), scene)?;
        let instances = InstanceTable::new(&self.gpu, &prepared, scene)?;
        self.scene = Some((prepared, Arc::new(instances)));
        Ok(())
    }

    /// Replaces the lights (scene lights and any procedural ones), effective next frame; they
    /// are written into the current light buffers where they fit, so moving lights every frame
    /// allocates nothing. A point
    /// or spot light without a range gets the effective range where its illuminance falls to
    /// [`RendererConfig::light_cutoff`] (after exposure).
    pub fn set_lights(&mut self, lights: &[SceneLight]) -> Result<(), RenderError> {
        self.lights = Arc::new(self.ranged_lights(lights, &self.config)?);
        self.light_sources = lights.to_vec();
        Ok(())
    }

    /// `lights` with the effective ranges of `config`'s cutoff and exposure, on the GPU.
    fn ranged_lights(
        &self,
        lights: &[SceneLight],
        config: &RendererConfig,
    ) -> Result<LightSet, RenderError> {
        let cutoff = config.light_cutoff / config.exposure.max(f32::MIN_POSITIVE);
        let lights = with_effective_ranges(lights, cutoff);
        let gpu = &self.gpu;
        LightSet::checked(gpu.device(), gpu.queue(), &lights, Some(&self.lights))
    }

    /// Replaces the decals (validated, their atlas packed with the default
    /// [`DecalAtlasConfig`]), effective next frame. Decals are culled into the same cell lists
    /// as lights and applied by forward shading before lighting, in their layer order
    /// ([`DecalSet::layer_order`]). A set with the current set's materials (decals added,
    /// removed or moved) keeps the packed atlas and writes only the decals' records; one that
    /// adds or removes materials keeps it too, each material the atlas holds (compared by
    /// value) in its place, removed ones' room given back and new ones written into free room;
    /// the atlas is packed again only when a new material finds no room or the configuration
    /// changes. The result says which happened.
    pub fn set_decals(&mut self, decals: &DecalSet) -> Result<DecalUpload, RenderError> {
        self.set_decals_with(decals, DecalAtlasConfig::default())
    }

    /// [`Renderer::set_decals`] with an atlas configuration.
    pub fn set_decals_with(
        &mut self,
        decals: &DecalSet,
        atlas: DecalAtlasConfig,
    ) -> Result<DecalUpload, RenderError> {
        let gpu = &self.gpu;
        let (set, upload) =
            GpuDecals::updated(gpu.device(), gpu.queue(), decals, atlas, &self.decals)?;
        self.decals = Arc::new(set);
        Ok(upload)
    }

    /// Replaces the particle systems (validated against this device), effective next frame.
    /// The next frame builds their GPU state and simulates `warmup_steps` fixed steps
    /// (`particles::FIXED_STEP` each) first, so they appear already under way; every frame
    /// after that advances them one fixed step. They are lit and drawn per
    /// [`RendererConfig::particle_lighting`]; [`FrameReport::particles`] counts them.
    pub fn set_particles(
        &mut self,
        system: &ParticleSystem,
        warmup_steps: u32,
    ) -> Result<(), RenderError> {
        system.validate(ParticleSimulation::max_capacity(self.gpu.device()))?;
        let generation = self.particles.as_ref().map_or(1, |p| p.generation + 1);
        self.particles = Some(ParticleInput {
            system: Arc::new(system.clone()),
            warmup_steps,
            generation,
        });
        Ok(())
    }

    /// Removes the particle systems.
    pub fn clear_particles(&mut self) {
        self.particles = None;
    }

    /// Changes the frame size; passes rebuild what depends on it on the next frame. A size of 0
    /// or past the device's largest texture side is [`ConfigError::FrameSize`](crate::frame::ConfigError::FrameSize), and the size
    /// stays as it was. Where the shadow settings fitted to the output change
    /// ([`RendererConfig::fitted_shadows`]), the shadow pass is built again (its atlas and
    /// static cache redrawn on the next frame); nothing else is.
    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), RenderError> {
        check_frame_size(&self.gpu, width, height)?;
        let resized = RendererConfig {
            width,
            height,
            ..self.config
        };
        if resized.fitted_shadows() != self.config.fitted_shadows()
            && self.pass::<ShadowPass>().is_some()
        {
            let rebuilt = ShadowPass::new(&self.gpu, &resized)?;
            if let Some(shadows) = self.pass_mut::<ShadowPass>() {
                *shadows = rebuilt;
            }
        }
        self.config = resized;
        Ok(())
    }

    /// Renders one frame into `target` (a `config.output_format` texture of the configured size).
    pub fn render(
        &mut self,
        camera: &FrameCamera,
        target: &wgpu::Texture,
    ) -> Result<FrameReport, RenderError> {
        self.render_with(camera, target, &[])
    }

    /// [`Renderer::render`] with further views ([`Renderer::render_views`], which checks them).
    fn render_with(
        &mut self,
        camera: &FrameCamera,
        target: &wgpu::Texture,
        views: &[ViewTarget<'_>],
    ) -> Result<FrameReport, RenderError> {
        if let Some(reason) = self.gpu.lost() {
            return Err(RenderError::Device(DeviceError::DeviceLost(reason)));
        }
        let scene = self
            .scene
            .clone()
            .ok_or(RenderError::Input(InputError::NoScene))?;
        check_target(&self.config, target)?;
        // Allocation failures while the frame is recorded come back as an error, not a panic.
        // In a browser the scope's answer is a promise the page's thread cannot wait for: an
        // allocation failure there reaches the device's uncaptured-error handler instead.
        #[cfg(not(target_arch = "wasm32"))]
        let out_of_memory = self
            .gpu
            .device()
            .push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let report = self.record_and_submit(camera, target, scene, views);
        #[cfg(not(target_arch = "wasm32"))]
        if let Some(error) = pollster::block_on(out_of_memory.pop()) {
            return Err(RenderError::Device(DeviceError::OutOfMemory(
                error.to_string(),
            )));
        }
        if let Some(reason) = self.gpu.lost() {
            return Err(RenderError::Device(DeviceError::DeviceLost(reason)));
        }
        report
    }

    /// [`Renderer::render`] once the frame's inputs are checked.
    fn record_and_submit(
        &mut self,
        camera: &FrameCamera,
        target: &wgpu::Texture,
        (scene, instances): (Arc<PreparedScene>, Arc<InstanceTable>),
        views: &[ViewTarget<'_>],
    ) -> Result<FrameReport, RenderError> {
        self.frame_index += 1;
        let frame = FrameInputs {
            gpu: self.gpu.clone(),
            config: self.config,
            camera: *camera,
            scene,
            instances,
            lights: Arc::clone(&self.lights),
            decals: Arc::clone(&self.decals),
            particles: self.particles.clone(),
            camera_uniform: self.camera_uniform.clone(),
            capture: self.capture_request.take(),
            index: self.frame_index,
            target_usage: target.usage(),
            target_format: target.format(),
        };
        let upload_started = Instant::now();
        self.camera_uniform.write(self.gpu.queue(), camera);
        for pass in &mut self.passes {
            pass.prepare(&frame)?;
        }
        let mut view_frames = self.prepare_views(&frame, views)?;
        let cpu_upload_ms = upload_started.elapsed().as_secs_f64() * 1e3;

        let started = Instant::now();
        let mut graph = RenderGraph::new();
        let c = &self.config;
        let output_desc = TextureDesc::new_2d(c.width, c.height, c.output_format);
        let output = graph.import_texture("output", output_desc, ImportAccess::ReadWrite);
        let mut resources = FrameResources::new(output);
        for pass in &self.passes {
            pass.add_to_graph(&mut graph, &frame, &mut resources)?;
        }
        resources.run_left_erasers(&mut graph)?;
        self.add_views_to_graph(&mut graph, &resources, &mut view_frames)?;
        let compilations = self.graph_cache.counts().0;
        let mut compiled = graph.compile_cached(&mut self.graph_cache)?;
        let graph_compiled = self.graph_cache.counts().0 > compilations;
        compiled.bind_texture(output, target);
        resources.bind_imports(&mut compiled);
        Self::bind_views(&mut compiled, &view_frames);
        let gpu = self.gpu.clone();
        let gpu = &gpu;
        let mut encoder = gpu.device().create_command_encoder(&Default::default());
        let pool = self.execute_graph(compiled, &mut encoder)?;
        for pass in &mut self.passes {
            pass.after_execute(&frame, &resources, &mut encoder);
        }
        self.views_after_execute(&view_frames, &mut encoder);
        self.profiler.resolve_queries(&mut encoder);
        let cpu_graph_ms = started.elapsed().as_secs_f64() * 1e3;

        let submit_started = Instant::now();
        self.in_flight
            .push_back(gpu.queue().submit([encoder.finish()]));
        let cpu_submit_ms = submit_started.elapsed().as_secs_f64() * 1e3;
        // Only the newest frames matter to `wait_for_frames_in_flight`.
        while self.in_flight.len() > MAX_TRACKED_FRAMES {
            self.in_flight.pop_front();
        }
        self.profiler
            .end_frame()
            .map_err(|e| RenderError::Device(DeviceError::Profiler(e.to_string())))?;
        let _ = gpu.device().poll(wgpu::PollType::Poll);
        let mut report = FrameReport {
            cpu_graph_ms,
            cpu_upload_ms,
            cpu_submit_ms,
            graph_compiled,
            pool,
            ..Default::default()
        };
        for pass in &mut self.passes {
            pass.after_submit(&frame, &mut report);
        }
        report.views = self.views_after_submit(&view_frames);
        report.timings = self
            .profiler
            .process_finished_frame(gpu.queue().get_timestamp_period())
            .map(|r| PassTiming::from_profiler(&r));
        Ok(report)
    }
}

/// `target` is a texture of `config`'s size and output format (or that format's linear twin,
/// `crate::frame_data::target_takes`).
fn check_target(config: &RendererConfig, target: &wgpu::Texture) -> Result<(), RenderError> {
    let size = target.size();
    if (size.width, size.height) != (config.width, config.height)
        || !crate::frame_data::target_takes(config.output_format, target.format())
    {
        return Err(RenderError::Input(InputError::TargetMismatch {
            actual: (size.width, size.height),
            actual_format: target.format(),
            expected: (config.width, config.height),
            expected_format: config.output_format,
        }));
    }
    Ok(())
}

/// What a configuration asks of the device, checked before anything is built; returns it with
/// its choices for the device made (the visibility raster).
fn check_config(gpu: &GpuContext, config: RendererConfig) -> Result<RendererConfig, RenderError> {
    let caps = gpu.capabilities();
    let config = RendererConfig {
        visibility_raster: (config.visibility_raster).for_device(caps, &gpu.device().limits()),
        ..config
    };
    let supported = caps.msaa_counts();
    if !supported.contains(&config.msaa) {
        return Err(RenderError::Config(ConfigError::SampleCount {
            asked: config.msaa,
            supported,
        }));
    }
    if config.scalarize && caps.subgroup.is_none() {
        return Err(RenderError::Config(ConfigError::NoSubgroup));
    }
    if !(config.light_cutoff.is_finite() && config.light_cutoff >= 0.0) {
        return Err(RenderError::Config(ConfigError::LightCutoff(
            config.light_cutoff,
        )));
    }
    check_frame_size(gpu, config.width, config.height)?;
    Ok(config)
}

/// A frame of `width` × `height` fits `gpu`: 1 to the largest texture side on each axis.
fn check_frame_size(gpu: &GpuContext, width: u32, height: u32) -> Result<(), RenderError> {
    let max = gpu.device().limits().max_texture_dimension_2d;
    if width == 0 || height == 0 || width > max || height > max {
        return Err(RenderError::Config(ConfigError::FrameSize {
            width,
            height,
            max,
        }));
    }
    Ok(())
}
