//! The engine-facing renderer: a device, a scene, lights and a camera in; a frame, per-pass GPU
//! timings and the compiled graph out.
//!
//! Each frame builds a [`RenderGraph`] from the passes in [`crate::passes`] (pre-Z → light
//! culling → forward → tonemap), compiles it and records it. The renderer never creates a window:
//! the caller owns the target texture.
//!
//! ```no_run
//! use renderer::frame::setup::{framing_camera, procedural_lights};
//! use renderer::frame::{RenderPath, Renderer, RendererConfig};
//! use renderer::scene::Scene;
//! use renderer::{GpuContext, GpuOptions};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // An engine would use GpuContext::from_parts(instance, adapter, device, queue).
//! let gpu = GpuContext::new_blocking(&GpuOptions::from_env())?;
//! let config = RendererConfig { width: 1280, height: 720, msaa: 4, path: RenderPath::Clustered, ..Default::default() };
//! let mut renderer = Renderer::new(&gpu, config)?;
//!
//! let scene = Scene::load("scene.glb")?;
//! renderer.prepare_scene(&scene);
//! let mut lights = scene.lights.clone();
//! lights.extend(procedural_lights(scene.bounds, 4096, 1, 0.5, 3.0));
//! renderer.set_lights(&lights);
//!
//! // The engine's own target: any texture of `config.output_format` with RENDER_ATTACHMENT
//! // (this helper makes one of the configured size).
//! let target = renderer::frame::setup::create_target(&gpu.device, &config);
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

pub mod capture;
mod pipelines;
mod prepared;
pub mod setup;

use std::collections::VecDeque;
use std::sync::Arc;
use std::time::Instant;

use glam::{Mat4, UVec2, UVec3, Vec3};
use shaders_gen::forward::forward;
use wgpu::util::DeviceExt as _;

pub use pipelines::Pipelines;
pub use prepared::{DrawItem, PreparedMaterial, PreparedScene};

use crate::culling::clustered::{ClusterCullConfig, ClusteredCulling};
use crate::culling::lists::CullCounters;
use crate::culling::overflow::{CounterReadback, grow_for};
use crate::culling::reference::{ClusterGrid, LightSphere};
use crate::culling::tiled::{TileCullConfig, TiledCulling};
use crate::culling::{CullError, max_index_entries};
use crate::graph::{
    BufferDesc, GraphError, ImportAccess, PassTiming, RenderGraph, TextureDesc, TransientPool,
};
use crate::scene::{LightKind, Scene, SceneLight};
use crate::shader::VariantError;
use crate::{GpuContext, passes};

/// How the forward pass finds its lights.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RenderPath {
    /// Every light at every pixel, without a depth pre-pass (overdraw shades every layer).
    Naive,
    /// Every light at every pixel after a depth pre-pass (the reference image of the culled
    /// paths).
    NaivePrez,
    /// Tiled culling (Forward+).
    Tiled,
    /// Tiled culling with the 2.5D depth mask.
    Depth25,
    /// Clustered culling, 16×8×24 froxels.
    Clustered,
}

impl RenderPath {
    fn list_axis(self) -> forward::List {
        match self {
            Self::Naive | Self::NaivePrez => forward::List::List0,
            Self::Tiled | Self::Depth25 => forward::List::List1,
            Self::Clustered => forward::List::List2,
        }
    }

    fn is_culled(self) -> bool {
        !matches!(self, Self::Naive | Self::NaivePrez)
    }

    /// Whether the frame runs the depth pre-pass.
    pub fn has_prepass(self) -> bool {
        self != Self::Naive
    }
}

/// What a frame shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FrameView {
    /// The shaded image.
    #[default]
    Lit,
    /// The light-count heatmap of the culled path's lists, with a legend.
    Heatmap,
}

/// Renderer settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RendererConfig {
    pub width: u32,
    pub height: u32,
    /// 1, 2, 4 or 8, as the adapter supports for Depth32Float and Rgba16Float.
    pub msaa: u32,
    pub path: RenderPath,
    /// Tile size of the tiled paths.
    pub tile: u32,
    /// Use subgroup variants where the device has SUBGROUP.
    pub scalarize: bool,
    /// Format of the caller's target (an sRGB format gets sRGB output).
    pub output_format: wgpu::TextureFormat,
    /// Ambient light, linear RGB.
    pub ambient: Vec3,
    pub exposure: f32,
    /// Shaded image or light-count heatmap.
    pub view: FrameView,
    /// Light count at which the heatmap saturates (red).
    pub heatmap_max: u32,
}

impl Default for RendererConfig {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 720,
            msaa: 4,
            path: RenderPath::Tiled,
            tile: 16,
            scalarize: false,
            output_format: wgpu::TextureFormat::Rgba8UnormSrgb,
            ambient: Vec3::splat(0.03),
            exposure: 1.0,
            view: FrameView::Lit,
            heatmap_max: 256,
        }
    }
}

/// Why the renderer cannot be set up or cannot render.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RenderError {
    #[error("MSAA {asked} is not supported by this device (supported: {supported:?})")]
    SampleCount { asked: u32, supported: Vec<u32> },
    #[error("scalarize was requested but the device has no SUBGROUP feature")]
    NoSubgroup,
    #[error("render() was called before prepare_scene()")]
    NoScene,
    #[error(
        "the light heatmap shows culled lists; the naive path has none (use tiled, 2.5D or clustered)"
    )]
    HeatmapNeedsLists,
    #[error(transparent)]
    Variant(#[from] VariantError),
    #[error(transparent)]
    Excluded(#[from] codegen::rt::ExcludedVariant),
    #[error(transparent)]
    Cull(#[from] CullError),
    #[error(transparent)]
    Graph(#[from] GraphError),
    #[error(
        "a frame capture reads the pre-Z depth; the naive path has none (use naive-prez or a culled path)"
    )]
    CaptureNeedsDepth,
    #[error(transparent)]
    Readback(#[from] crate::GpuError),
    #[error("GPU timing failed: {0}")]
    Profiler(String),
}

/// The camera of a frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameCamera {
    pub view: Mat4,
    /// A wgpu (depth 0..1) perspective projection.
    pub projection: Mat4,
    pub eye: Vec3,
    pub near: f32,
    pub far: f32,
}

/// What a frame reports back.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameReport {
    /// Per-pass GPU times of the newest frame whose timestamps have arrived.
    pub timings: Option<Vec<PassTiming>>,
    /// CPU time to build, compile and encode the frame graph, in milliseconds.
    pub cpu_graph_ms: f64,
    /// CPU time to write the frame's uniforms and culling items before that (grows with the
    /// light count), in milliseconds.
    pub cpu_upload_ms: f64,
    /// The compiled graph as Graphviz DOT.
    pub graph_dot: String,
    /// Culling counters of the newest frame whose copy has arrived (read asynchronously).
    /// `dropped > 0` means lights were left out of some lists that frame; the renderer logs a
    /// warning and grows the index list for the next frame where the device allows.
    pub culling: Option<CullCounters>,
}

/// The light culler of the configured path.
#[derive(Debug, Clone)]
pub enum Culler {
    Naive,
    Tiled(Arc<TiledCulling>),
    Clustered(Arc<ClusteredCulling>),
}

impl Culler {
    /// The light lists this culler writes (none on the naive paths).
    pub fn lists(&self) -> Option<&crate::culling::lists::LightLists> {
        match self {
            Self::Tiled(c) => Some(&c.lists),
            Self::Clustered(c) => Some(&c.lists),
            Self::Naive => None,
        }
    }

    /// Whether the culling pass reads the depth buffer: tiled always; clustered only to skip
    /// empty froxels.
    pub fn reads_depth(&self) -> bool {
        match self {
            Self::Tiled(_) => true,
            Self::Clustered(c) => c.config.skip_empty,
            Self::Naive => false,
        }
    }
}

/// Everything the passes of one frame need on the GPU.
#[derive(Debug)]
pub struct FrameGpu {
    pub msaa: u32,
    pub scene: Arc<PreparedScene>,
    pub pipelines: Arc<Pipelines>,
    pub culler: Culler,
    pub prez_camera: wgpu::BindGroup,
    pub camera: wgpu::Buffer,
    pub lighting: wgpu::Buffer,
    pub lights: wgpu::Buffer,
    pub directional: wgpu::Buffer,
    pub tonemap_params: wgpu::Buffer,
    pub heatmap_params: wgpu::Buffer,
    pub clear_color: wgpu::Color,
    pub eye: Vec3,
}

impl FrameGpu {
    /// The light lists of a culled path (the heatmap is only built for those).
    pub fn lists(&self) -> &crate::culling::lists::LightLists {
        self.culler
            .lists()
            .expect("Pipelines::new refuses a heatmap on the naive path")
    }

    /// Group 0 of the forward program: camera, lighting, lights and, when culled, the lists.
    pub fn forward_frame_group(&self, device: &wgpu::Device) -> wgpu::BindGroup {
        let mut entries = vec![
            wgpu::BindGroupEntry {
                binding: 0,
                resource: self.camera.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: self.lighting.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: self.lights.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: self.directional.as_entire_binding(),
            },
        ];
        if let Some(l) = self.culler.lists() {
            entries.push(wgpu::BindGroupEntry {
                binding: 4,
                resource: l.grid.as_entire_binding(),
            });
            entries.push(wgpu::BindGroupEntry {
                binding: 5,
                resource: l.indices.as_entire_binding(),
            });
        }
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("forward frame"),
            layout: &self.pipelines.forward_program.bind_group_layouts[0],
            entries: &entries,
        })
    }
}

/// The renderer.
pub struct Renderer {
    gpu: GpuContext,
    config: RendererConfig,
    pipelines: Arc<Pipelines>,
    culler: Culler,
    scene: Option<Arc<PreparedScene>>,
    punctual: Vec<forward::GpuLight>,
    directional: Vec<forward::GpuLight>,
    spheres: Vec<LightSphere>,
    pool: TransientPool,
    profiler: wgpu_profiler::GpuProfiler,
    counters: CounterReadback,
    frame_index: u64,
    index_capacity: u32,
    last_counters: Option<CullCounters>,
    buffers: FrameBuffers,
    /// Submissions of frames that may still run on the GPU, oldest first.
    in_flight: VecDeque<wgpu::SubmissionIndex>,
    /// Probe stride of a capture asked for the next frame.
    capture_request: Option<u32>,
    capture_kernel: Option<Arc<capture::ProbePipeline>>,
    pending_capture: Option<capture::PendingCapture>,
}

/// Per-frame GPU data kept across frames: uniforms rewritten each frame, light storage rewritten
/// by `set_lights`, so a frame allocates nothing for them.
#[derive(Debug)]
struct FrameBuffers {
    camera: wgpu::Buffer,
    lighting: wgpu::Buffer,
    tonemap: wgpu::Buffer,
    heatmap: wgpu::Buffer,
    prez_camera: wgpu::BindGroup,
    lights: wgpu::Buffer,
    directional: wgpu::Buffer,
}

impl FrameBuffers {
    fn new(device: &wgpu::Device, pipelines: &Pipelines) -> Self {
        let uniform = |label, size| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let camera = uniform("camera", size_of::<forward::Camera>() as u64);
        let prez_camera = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("pre-z camera"),
            layout: &pipelines.prez_program.bind_group_layouts[0],
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: camera.as_entire_binding(),
            }],
        });
        Self {
            lighting: uniform("lighting", size_of::<forward::Lighting>() as u64),
            tonemap: uniform(
                "tonemap",
                size_of::<shaders_gen::forward::tonemap::TonemapParams>() as u64,
            ),
            heatmap: uniform(
                "heatmap",
                size_of::<shaders_gen::forward::heatmap::HeatmapParams>() as u64,
            ),
            camera,
            prez_camera,
            lights: light_storage(device, "lights", &[]),
            directional: light_storage(device, "directional lights", &[]),
        }
    }
}

/// A storage buffer holding `lights` (at least one element, so the binding is never empty).
fn light_storage(device: &wgpu::Device, label: &str, lights: &[forward::GpuLight]) -> wgpu::Buffer {
    let placeholder = [forward::GpuLight::new(
        Vec3::ZERO,
        0.0,
        Vec3::ZERO,
        0.0,
        Vec3::Z,
        0,
        1.0,
        1.0,
    )];
    let contents = if lights.is_empty() {
        &placeholder[..]
    } else {
        lights
    };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(contents),
        usage: wgpu::BufferUsages::STORAGE,
    })
}

impl std::fmt::Debug for Renderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Renderer")
            .field("config", &self.config)
            .field("lights", &self.punctual.len())
            .field("directional", &self.directional.len())
            .finish_non_exhaustive()
    }
}

/// Submissions the renderer remembers for `wait_for_frames_in_flight`.
const MAX_TRACKED_FRAMES: usize = 8;

/// Range standing in for "infinite" in culling spheres.
const INFINITE_RANGE: f32 = 1.0e30;

impl Renderer {
    pub fn new(gpu: &GpuContext, config: RendererConfig) -> Result<Self, RenderError> {
        let caps = gpu.capabilities();
        let supported = caps.msaa_counts();
        if !supported.contains(&config.msaa) {
            return Err(RenderError::SampleCount {
                asked: config.msaa,
                supported,
            });
        }
        if config.scalarize && caps.subgroup.is_none() {
            return Err(RenderError::NoSubgroup);
        }
        let settings = wgpu_profiler::GpuProfilerSettings {
            enable_debug_groups: false,
            ..Default::default()
        };
        let pipelines = Arc::new(Pipelines::new(&gpu.device, caps, &config)?);
        Ok(Self {
            pipelines: Arc::clone(&pipelines),
            culler: Culler::Naive,
            gpu: gpu.clone(),
            config,
            scene: None,
            punctual: Vec::new(),
            directional: Vec::new(),
            spheres: Vec::new(),
            pool: TransientPool::new(),
            profiler: wgpu_profiler::GpuProfiler::new(&gpu.device, settings)
                .map_err(|e| RenderError::Profiler(e.to_string()))?,
            counters: CounterReadback::new(&gpu.device),
            buffers: FrameBuffers::new(&gpu.device, &pipelines),
            frame_index: 0,
            index_capacity: max_index_entries(&gpu.device).min(1 << 22),
            last_counters: None,
            in_flight: VecDeque::new(),
            capture_request: None,
            capture_kernel: None,
            pending_capture: None,
        })
    }

    pub fn config(&self) -> &RendererConfig {
        &self.config
    }

    /// Uploads a scene; it replaces the previous one.
    pub fn prepare_scene(&mut self, scene: &Scene) {
        self.scene = Some(PreparedScene::new(
            &self.gpu.device,
            &self.gpu.queue,
            scene,
            &self.pipelines.forward_program,
            &self.pipelines.prez_mask_program,
        ));
    }

    /// Replaces the lights (scene lights and any procedural ones), effective next frame.
    pub fn set_lights(&mut self, lights: &[SceneLight]) {
        self.punctual.clear();
        self.directional.clear();
        self.spheres.clear();
        for l in lights {
            let range = l.range.unwrap_or(0.0);
            let (kind, cos_inner, cos_outer) = match l.kind {
                LightKind::Point => (forward::KIND_POINT, 1.0, 1.0),
                LightKind::Spot {
                    inner_cone,
                    outer_cone,
                } => (forward::KIND_SPOT, inner_cone.cos(), outer_cone.cos()),
                LightKind::Directional => (forward::KIND_DIRECTIONAL, 1.0, 1.0),
            };
            let gpu_light = forward::GpuLight::new(
                l.position,
                range,
                l.color,
                l.intensity,
                l.direction,
                kind,
                cos_inner,
                cos_outer,
            );
            if l.kind == LightKind::Directional {
                self.directional.push(gpu_light);
                continue;
            }
            let reach = l.range.unwrap_or(INFINITE_RANGE);
            self.spheres.push(match l.kind {
                LightKind::Spot { outer_cone, .. } => {
                    LightSphere::spot(l.position, l.direction, outer_cone.cos(), reach)
                }
                _ => LightSphere {
                    center: l.position,
                    radius: reach,
                },
            });
            self.punctual.push(gpu_light);
        }
        let device = &self.gpu.device;
        self.buffers.lights = light_storage(device, "lights", &self.punctual);
        self.buffers.directional = light_storage(device, "directional lights", &self.directional);
    }

    /// Changes the frame size; culling buffers follow on the next frame.
    pub fn resize(&mut self, width: u32, height: u32) {
        self.config.width = width;
        self.config.height = height;
        self.culler = Culler::Naive;
    }

    fn ensure_culler(&mut self, camera: &FrameCamera) -> Result<(), RenderError> {
        let c = &self.config;
        let items = (self.spheres.len() as u32).max(1).next_power_of_two();
        let index_capacity = self.index_capacity;
        let has_blend = self.scene.as_ref().is_some_and(|s| {
            s.materials
                .iter()
                .any(|m| m.alpha_mode == crate::scene::AlphaMode::Blend)
        });
        let fits = |capacity: u32| capacity >= items;
        let ok = match (&self.culler, c.path) {
            (Culler::Naive, RenderPath::Naive | RenderPath::NaivePrez) => true,
            (Culler::Tiled(t), RenderPath::Tiled | RenderPath::Depth25) => {
                fits(t.config.item_capacity)
                    && t.config.index_capacity == index_capacity
                    && t.config.include_transparent == has_blend
            }
            (Culler::Clustered(k), RenderPath::Clustered) => {
                fits(k.config.item_capacity)
                    && k.config.index_capacity == index_capacity
                    && k.config.skip_empty == (!has_blend && c.msaa == 1)
                    && k.config.grid.near == camera.near
                    && k.config.grid.far == camera.far
            }
            _ => false,
        };
        if ok {
            return Ok(());
        }
        let scalarize = c.scalarize;
        self.culler = match c.path {
            RenderPath::Naive | RenderPath::NaivePrez => Culler::Naive,
            RenderPath::Tiled | RenderPath::Depth25 => {
                let config = TileCullConfig {
                    tile: c.tile,
                    msaa: c.msaa,
                    scalarize,
                    depth_mask: c.path == RenderPath::Depth25,
                    include_transparent: has_blend,
                    max_per_tile: 1024,
                    index_capacity,
                    item_capacity: items,
                };
                Culler::Tiled(Arc::new(TiledCulling::new(
                    &self.gpu, config, c.width, c.height,
                )?))
            }
            RenderPath::Clustered => {
                let grid = ClusterGrid {
                    x: 16,
                    y: 8,
                    z: 24,
                    near: camera.near,
                    far: camera.far,
                };
                let config = ClusterCullConfig {
                    grid,
                    msaa: c.msaa,
                    scalarize,
                    // Skipping froxels without a depth sample is exact only when every shaded
                    // point is a depth sample: no blended surfaces (absent from pre-Z) and no
                    // MSAA (an edge fragment is shaded at the pixel centre, which may lie in a
                    // froxel no visible sample occupies).
                    skip_empty: !has_blend && c.msaa == 1,
                    max_per_cluster: 1024,
                    index_capacity,
                    item_capacity: items,
                };
                Culler::Clustered(Arc::new(ClusteredCulling::new(
                    &self.gpu, config, c.width, c.height,
                )?))
            }
        };
        Ok(())
    }

    /// Renders one frame into `target` (a `config.output_format` texture of the configured size).
    pub fn render(
        &mut self,
        camera: &FrameCamera,
        target: &wgpu::Texture,
    ) -> Result<FrameReport, RenderError> {
        let scene = self.scene.clone().ok_or(RenderError::NoScene)?;
        self.ensure_culler(camera)?;
        if self.capture_request.is_some() && self.capture_kernel.is_none() {
            let kernel = capture::ProbePipeline::new(&self.gpu, self.config.msaa)?;
            self.capture_kernel = Some(Arc::new(kernel));
        }
        let upload_started = Instant::now();
        let gpu = &self.gpu;
        let c = self.config;
        let screen = UVec2::new(c.width, c.height);
        let cam = forward::Camera::new(
            camera.view,
            camera.projection,
            camera.projection * camera.view,
            camera.eye,
        );
        let tiles = UVec2::new(c.width.div_ceil(c.tile), c.height.div_ceil(c.tile));
        let lighting = forward::Lighting::new(
            c.ambient,
            self.punctual.len() as u32,
            screen,
            tiles,
            UVec3::new(16, 8, 24),
            c.tile,
            camera.near,
            camera.far,
            self.directional.len() as u32,
        );
        let b = &self.buffers;
        gpu.queue
            .write_buffer(&b.camera, 0, bytemuck::bytes_of(&cam));
        gpu.queue
            .write_buffer(&b.lighting, 0, bytemuck::bytes_of(&lighting));
        let tonemap = shaders_gen::forward::tonemap::TonemapParams::new(c.exposure);
        gpu.queue
            .write_buffer(&b.tonemap, 0, bytemuck::bytes_of(&tonemap));
        if c.view == FrameView::Heatmap {
            let heatmap = shaders_gen::forward::heatmap::HeatmapParams::new(
                camera.projection.inverse(),
                screen,
                tiles,
                UVec3::new(16, 8, 24),
                c.tile,
                camera.near,
                camera.far,
                c.heatmap_max,
            );
            gpu.queue
                .write_buffer(&b.heatmap, 0, bytemuck::bytes_of(&heatmap));
        }
        match &self.culler {
            Culler::Tiled(t) => {
                let items: Vec<_> = self
                    .spheres
                    .iter()
                    .map(|s| shaders_gen::culling::tile_cull::CullSphere::new(s.center, s.radius))
                    .collect();
                t.upload(gpu, camera.view, camera.projection, screen, &items)?;
            }
            Culler::Clustered(k) => {
                let items: Vec<_> = self
                    .spheres
                    .iter()
                    .map(|s| {
                        shaders_gen::culling::cluster_cull::CullSphere::new(s.center, s.radius)
                    })
                    .collect();
                k.upload(gpu, camera.view, camera.projection, &items)?;
            }
            Culler::Naive => {}
        }
        let cpu_upload_ms = upload_started.elapsed().as_secs_f64() * 1e3;
        let started = Instant::now();
        let frame = Arc::new(FrameGpu {
            msaa: c.msaa,
            scene,
            pipelines: Arc::clone(&self.pipelines),
            culler: self.culler.clone(),
            prez_camera: b.prez_camera.clone(),
            camera: b.camera.clone(),
            lighting: b.lighting.clone(),
            lights: b.lights.clone(),
            directional: b.directional.clone(),
            tonemap_params: b.tonemap.clone(),
            heatmap_params: b.heatmap.clone(),
            clear_color: wgpu::Color::BLACK,
            eye: camera.eye,
        });

        let mut graph = RenderGraph::new();
        let output_desc = TextureDesc::new_2d(c.width, c.height, c.output_format);
        let mut output = graph.import_texture("output", output_desc, ImportAccess::ReadWrite);
        let depth = c
            .path
            .has_prepass()
            .then(|| passes::prez::add(&mut graph, &frame, c.width, c.height));
        // Every culled path runs the pre-pass (culling reads its depth).
        let culled_depth = depth.filter(|_| !matches!(self.culler, Culler::Naive));
        let lists = match culled_depth {
            None => None,
            Some(depth) => {
                let (grid_bytes, index_bytes) = self.culler.lists().map_or((0, 0), |l| l.bytes());
                let mut grid = graph.import_buffer(
                    "light grid",
                    BufferDesc { size: grid_bytes },
                    ImportAccess::ReadWrite,
                );
                let mut indices = graph.import_buffer(
                    "light indices",
                    BufferDesc { size: index_bytes },
                    ImportAccess::ReadWrite,
                );
                passes::light_cull::add(&mut graph, &frame, depth, &mut grid, &mut indices);
                Some((grid, indices))
            }
        };
        match (c.view, lists, depth) {
            (FrameView::Heatmap, Some(lists), Some(depth)) => {
                passes::heatmap::add(&mut graph, &frame, depth, lists, &mut output);
            }
            _ => {
                let hdr = passes::forward::add(&mut graph, &frame, depth, lists, c.width, c.height);
                passes::tonemap::add(&mut graph, &frame, hdr, &mut output);
            }
        }

        let probe = match (self.capture_request, depth, &self.capture_kernel) {
            (Some(stride), Some(depth), Some(kernel)) => {
                let probe = Arc::new(capture::ProbeGpu::new(&gpu.device, kernel, screen, stride));
                let mut handle = graph.import_buffer(
                    "depth probes",
                    BufferDesc {
                        size: probe.output.size(),
                    },
                    ImportAccess::ReadWrite,
                );
                passes::depth_probe::add(&mut graph, &probe, depth, &mut handle);
                Some((probe, handle))
            }
            _ => None,
        };

        let mut compiled = graph.compile()?;
        let graph_dot = compiled.to_dot();
        compiled.bind_texture(output, target);
        if let Some((probe, handle)) = &probe {
            compiled.bind_buffer(*handle, &probe.output);
        }
        if let (Some((grid, indices)), Some(l)) = (lists, self.culler.lists()) {
            compiled
                .bind_buffer(grid, &l.grid)
                .bind_buffer(indices, &l.indices);
        }
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        compiled.execute(&gpu.device, &mut encoder, &mut self.pool, &self.profiler)?;
        self.frame_index += 1;
        if let Some(l) = self.culler.lists() {
            self.counters
                .record(&mut encoder, &l.counters, self.frame_index);
        }
        let capture = probe.map(|(probe, _)| self.record_capture(&mut encoder, probe, camera));
        self.profiler.resolve_queries(&mut encoder);
        let cpu_graph_ms = started.elapsed().as_secs_f64() * 1e3;
        let gpu = &self.gpu;
        self.in_flight
            .push_back(gpu.queue.submit([encoder.finish()]));
        // Only the newest frames matter to `wait_for_frames_in_flight`.
        while self.in_flight.len() > MAX_TRACKED_FRAMES {
            self.in_flight.pop_front();
        }
        if capture.is_some() {
            self.pending_capture = capture;
            self.capture_request = None;
        }
        self.counters.after_submit();
        self.profiler
            .end_frame()
            .map_err(|e| RenderError::Profiler(e.to_string()))?;
        let _ = gpu.device.poll(wgpu::PollType::Poll);
        let timings = self
            .profiler
            .process_finished_frame(gpu.queue.get_timestamp_period())
            .map(|r| PassTiming::from_profiler(&r));
        self.poll_counters();
        Ok(FrameReport {
            timings,
            cpu_graph_ms,
            cpu_upload_ms,
            graph_dot,
            culling: self.last_counters,
        })
    }

    /// The capture of a frame being encoded: probes plus a copy of the light grid.
    fn record_capture(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        probe: Arc<capture::ProbeGpu>,
        camera: &FrameCamera,
    ) -> capture::PendingCapture {
        use crate::culling::reference::Method;
        let c = &self.config;
        let method = match &self.culler {
            Culler::Tiled(t) if t.config.depth_mask => Some(Method::Depth25 { tile: c.tile }),
            Culler::Tiled(_) => Some(Method::Tiled { tile: c.tile }),
            Culler::Clustered(k) => Some(Method::Clustered {
                grid: k.config.grid,
                skip_empty: k.config.skip_empty,
            }),
            Culler::Naive => None,
        };
        let grid_copy = self.culler.lists().map(|l| {
            let copy = self.gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("captured light grid"),
                size: l.grid.size(),
                usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            encoder.copy_buffer_to_buffer(&l.grid, 0, &copy, 0, l.grid.size());
            copy
        });
        capture::PendingCapture {
            probe,
            stride: self.capture_request.unwrap_or(1),
            msaa: c.msaa,
            camera: crate::culling::reference::CullCamera {
                view: camera.view,
                projection: camera.projection,
                width: c.width,
                height: c.height,
            },
            lights: self.spheres.clone(),
            method,
            grid_copy,
        }
    }

    /// Asks the next frame to capture its depth at every `stride`-th pixel (both ways) and its
    /// light grid, for [`Self::take_capture`]. Needs the depth pre-pass.
    pub fn capture_next_frame(&mut self, stride: u32) -> Result<(), RenderError> {
        if !self.config.path.has_prepass() {
            return Err(RenderError::CaptureNeedsDepth);
        }
        self.capture_request = Some(stride.max(1));
        Ok(())
    }

    /// Reads back the newest captured frame (blocking); `None` if no capture was rendered since
    /// the last call.
    pub fn take_capture(&mut self) -> Result<Option<capture::FrameCapture>, RenderError> {
        match self.pending_capture.take() {
            Some(p) => Ok(Some(p.read_back(&self.gpu)?)),
            None => Ok(None),
        }
    }

    /// Blocks until at most `max` submitted frames may still be running on the GPU, so a caller
    /// can keep the GPU busy without running ahead of the timestamp queries.
    pub fn wait_for_frames_in_flight(&mut self, max: usize) -> Result<(), RenderError> {
        while self.in_flight.len() > max {
            if let Some(index) = self.in_flight.pop_front() {
                self.gpu
                    .device
                    .poll(wgpu::PollType::Wait {
                        submission_index: Some(index),
                        timeout: None,
                    })
                    .map_err(crate::GpuError::Poll)?;
            }
        }
        Ok(())
    }

    /// Per-pass timings of every frame whose timestamps have arrived and were not yet returned
    /// (by `render`'s report or an earlier call), oldest first. Does not block.
    pub fn drain_timings(&mut self) -> Vec<Vec<PassTiming>> {
        let _ = self.gpu.device.poll(wgpu::PollType::Poll);
        let mut frames = Vec::new();
        while let Some(r) = self
            .profiler
            .process_finished_frame(self.gpu.queue.get_timestamp_period())
        {
            frames.push(PassTiming::from_profiler(&r));
        }
        frames
    }

    /// Picks up culling counters that have arrived; on overflow, warns and grows the index list
    /// for the next frame (up to one storage binding; past that the overflow stays reported).
    fn poll_counters(&mut self) -> Option<CullCounters> {
        let (_, counters) = self.counters.poll(&self.gpu.device)?;
        self.last_counters = Some(counters);
        if counters.dropped > 0 {
            let current = crate::culling::overflow::Capacities {
                per_cell: 1024,
                index: self.index_capacity,
            };
            let limit = max_index_entries(&self.gpu.device);
            let grown = grow_for(&counters, current, 1024)
                .map(|c| c.index.min(limit))
                .filter(|&index| index > self.index_capacity);
            log::warn!(
                "light culling dropped {} list entries ({} cells over their 1024-item limit, {} \
                 entries requested of {}); {}",
                counters.dropped,
                counters.overflow_cells,
                counters.requested_entries,
                self.index_capacity,
                if grown.is_some() {
                    "growing the index list for the next frame"
                } else {
                    "the per-cell limit is reached: use smaller tiles, 2.5D or fewer lights per cell"
                }
            );
            if let Some(index) = grown {
                self.index_capacity = index;
            }
        }
        Some(counters)
    }

    /// The light culler of the configured path (built on the first frame; `Naive` before), for
    /// tools that report on it: its lists' cells and bytes, whether it reads depth.
    pub fn culler(&self) -> &Culler {
        &self.culler
    }

    /// The newest culling counters that have arrived, polling first.
    pub fn culling_counters(&mut self) -> Option<CullCounters> {
        self.poll_counters();
        self.last_counters
    }

    /// Waits for the GPU and returns the timings of the frames that finished (tools and tests).
    pub fn finish(&mut self) -> Option<Vec<PassTiming>> {
        let _ = self.gpu.wait_idle();
        self.poll_counters();
        let mut newest = None;
        while let Some(r) = self
            .profiler
            .process_finished_frame(self.gpu.queue.get_timestamp_period())
        {
            newest = Some(PassTiming::from_profiler(&r));
        }
        newest
    }
}
