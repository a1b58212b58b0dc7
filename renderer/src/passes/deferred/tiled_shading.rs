//! The TBDR shading pass: one `tbdr::shade` dispatch over the G-buffer (one workgroup per
//! tile) writes the resolved HDR image. It owns the light spheres the kernel culls, its
//! parameters, and, when asked to record, the edge bits and a copy of the G-buffer that tools
//! and tests read back.
//!
//! On the traditional deferred path ([`RenderPath::Deferred`]) the same dispatch is the
//! *deferred base* pass: no punctual lights (sky, ambient, emissive and directional lights
//! only), every frame's edge pixels marked in a buffer that the light volumes read
//! ([`FrameResources::deferred_edges`]).

use crate::frame_data::ConfigError;
use shaders_gen::deferred::{gbuffer_read::tbdr_gbuffer, tbdr};
use shaders_gen::shared::light_spheres;

use crate::GpuContext;
use crate::frame_data::{
    FrameInputs, FrameResources, FrameView, GBufferHandles, HDR_FORMAT, RenderError, RenderPath,
    RendererConfig, ShadowResources,
};
use crate::graph::{Handle, PassBuilder, RenderGraph, Texture, TextureAccess, TextureDesc};
use crate::passes::{Pass, groups_8x8};
use crate::shader::ShaderProgram;

/// What a recording frame left: which pixels were shaded per sample, and the G-buffer.
#[derive(Debug, Clone)]
#[cfg(any(test, feature = "internals"))]
pub struct TbdrRecord {
    pub width: u32,
    pub height: u32,
    pub msaa: u32,
    /// Bit `y · width + x` set where pixel `(x, y)` was shaded per sample.
    pub edge_bits: Vec<u32>,
    /// Per sample (samples of a pixel together, pixels row-major): depth, albedo and
    /// metalness, normals, base radiance and roughness, view depth (`tbdr::CAPTURE_WORDS`
    /// floats).
    pub gbuffer: Vec<f32>,
}

#[cfg(any(test, feature = "internals"))]
impl TbdrRecord {
    /// Whether pixel `(x, y)` was shaded per sample.
    #[cfg(any(test, feature = "internals"))]
    pub fn is_edge(&self, x: u32, y: u32) -> bool {
        let bit = (y * self.width + x) as usize;
        self.edge_bits
            .get(bit / 32)
            .is_some_and(|w| w & (1 << (bit % 32)) != 0)
    }

    /// Pixels shaded per sample.
    #[cfg(any(test, feature = "internals"))]
    pub fn edge_count(&self) -> u32 {
        self.edge_bits.iter().map(|w| w.count_ones()).sum()
    }

    /// Sample `s` of pixel `(x, y)`: `tbdr::CAPTURE_WORDS` floats.
    #[cfg(any(test, feature = "internals"))]
    pub fn sample(&self, x: u32, y: u32, s: u32) -> &[f32] {
        let words = tbdr::CAPTURE_WORDS as usize;
        let at = (((y * self.width + x) * self.msaa + s) as usize) * words;
        self.gbuffer.get(at..at + words).unwrap_or(&[])
    }
}

/// Buffers of a recording frame.
#[derive(Debug)]
struct Recording {
    size: (u32, u32),
    msaa: u32,
    edge_bits: wgpu::Buffer,
    gbuffer: wgpu::Buffer,
}

/// The TBDR shading pass.
#[derive(Debug)]
pub struct TbdrPass {
    gpu: GpuContext,
    program: ShaderProgram,
    shade: wgpu::ComputePipeline,
    capture: wgpu::ComputePipeline,
    params: wgpu::Buffer,
    spheres: wgpu::Buffer,
    /// What `EDGE_BITS` and `CAPTURE` bind when not recording: one buffer each, since WebGPU
    /// forbids one buffer at two writable bindings of a group.
    unused_edges: wgpu::Buffer,
    unused_capture: wgpu::Buffer,
    /// The deferred base pass of [`RenderPath::Deferred`]: no punctual lights, edges always
    /// marked (in `edges`, or the recording's buffer).
    base_only: bool,
    /// The base pass's edge bits, a bit per pixel.
    edges: wgpu::Buffer,
    /// Whether frames record their edges and G-buffer.
    record: bool,
    recording: Option<Recording>,
}

impl TbdrPass {
    pub fn new(gpu: &GpuContext, config: &RendererConfig) -> Result<Self, RenderError> {
        let tile = match config.tile {
            8 => tbdr::Tile::T8,
            16 => tbdr::Tile::T16,
            t => return Err(RenderError::Config(ConfigError::TbdrTile(t))),
        };
        let msaa = variant_msaa(config.msaa)?;
        let base_only = config.path == RenderPath::Deferred;
        let key = tbdr::VariantKey {
            tile,
            msaa,
            scalarize: config.scalarize && !base_only,
            defer: config.path == RenderPath::TbdrPerSample && config.msaa > 1,
        };
        let program = gpu.program(tbdr::variant(key)?)?;
        let storage = |label, size| {
            gpu.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        Ok(Self {
            gpu: gpu.clone(),
            shade: program.compute_pipeline(gpu.device(), "shade")?,
            capture: program.compute_pipeline(gpu.device(), "capture_gbuffer")?,
            program,
            params: gpu.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some("tbdr params"),
                size: size_of::<tbdr::TbdrParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            spheres: storage("tbdr light spheres", 16),
            unused_edges: storage("tbdr unused edge bits", 16),
            unused_capture: storage("tbdr unused capture", 16),
            base_only,
            edges: storage("deferred edge bits", 16),
            record: false,
            recording: None,
        })
    }

    /// Makes every following frame record which pixels it shaded per sample, and a copy of its
    /// G-buffer ([`Self::recorded`]). Costs a G-buffer copy per frame: for tools and tests.
    #[cfg(any(test, feature = "internals"))]
    pub fn set_recording(&mut self, on: bool) {
        self.record = on;
        if !on {
            self.recording = None;
        }
    }

    /// What the last recording frame left (blocking readback); `None` before one.
    #[cfg(any(test, feature = "internals"))]
    pub fn recorded(&self) -> Result<Option<TbdrRecord>, RenderError> {
        let Some(r) = &self.recording else {
            return Ok(None);
        };
        let (device, queue) = (self.gpu.device(), self.gpu.queue());
        Ok(Some(TbdrRecord {
            width: r.size.0,
            height: r.size.1,
            msaa: r.msaa,
            edge_bits: crate::readback::read_buffer(device, queue, &r.edge_bits)?,
            gbuffer: crate::readback::read_buffer(device, queue, &r.gbuffer)?,
        }))
    }
}

/// The `tbdr` module's MSAA axis value for `msaa` samples.
pub(super) fn variant_msaa(msaa: u32) -> Result<tbdr::Msaa, RenderError> {
    tbdr::Msaa::from_value(msaa).ok_or_else(|| {
        RenderError::Config(ConfigError::SampleCount {
            asked: msaa,
            supported: tbdr::Msaa::ALL.iter().map(|m| m.value()).collect(),
        })
    })
}

/// The `tbdr` module's parameters for `frame`, with `light_count` punctual lights culled and
/// shaded, and edge pixels marked in `EDGE_BITS` when `record_edges` (public for tools and tests
/// that run the kernel themselves).
pub fn kernel_params(
    frame: &FrameInputs,
    light_count: u32,
    record_edges: bool,
) -> tbdr::TbdrParams {
    let c = &frame.config;
    let cam = &frame.camera;
    tbdr::TbdrParams::new(
        cam.view,
        cam.projection,
        cam.projection.inverse(),
        cam.view.inverse(),
        cam.eye,
        light_count,
        c.sky,
        frame.lights.directional.len() as u32,
        frame.screen(),
        u32::from(c.view == FrameView::ShadingFrequency),
        u32::from(record_edges),
        c.edges.depth,
        c.edges.normal_cos,
        c.edges.material,
        u32::from(cam.orthographic),
    )
}

/// Writes the frame's light spheres (centre, radius) to `buffer`, growing it to a power of two
/// when they do not fit.
pub(super) fn upload_spheres(gpu: &GpuContext, buffer: &mut wgpu::Buffer, frame: &FrameInputs) {
    let spheres: Vec<glam::Vec4> = frame
        .lights
        .spheres
        .iter()
        .map(|s| s.center.extend(s.radius))
        .collect();
    let bytes: &[u8] = bytemuck::cast_slice(&spheres);
    if bytes.len() as u64 > buffer.size() {
        *buffer = gpu.device().create_buffer(&wgpu::BufferDescriptor {
            label: Some("tbdr light spheres"),
            size: (bytes.len() as u64).next_power_of_two(),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
    }
    gpu.queue().write_buffer(buffer, 0, bytes);
}

impl Pass for TbdrPass {
    fn name(&self) -> &'static str {
        if self.base_only {
            "deferred base"
        } else {
            "tbdr shading"
        }
    }

    fn prepare(&mut self, frame: &FrameInputs) -> Result<(), RenderError> {
        let c = &frame.config;
        let pixels = u64::from(c.width) * u64::from(c.height);
        let params = if self.base_only {
            let edge_bytes = pixels.div_ceil(32) * 4;
            if edge_bytes > self.edges.size() {
                self.edges = self.gpu.device().create_buffer(&wgpu::BufferDescriptor {
                    label: Some("deferred edge bits"),
                    size: edge_bytes,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
            }
            kernel_params(frame, 0, true)
        } else {
            upload_spheres(&self.gpu, &mut self.spheres, frame);
            kernel_params(frame, frame.lights.punctual.len() as u32, self.record)
        };
        self.gpu
            .queue()
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let size = (c.width, c.height);
        let stale = |r: &Recording| r.size != size || r.msaa != c.msaa;
        if self.record && self.recording.as_ref().is_none_or(stale) {
            let buffer = |label, size: u64| {
                self.gpu.device().create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: size.max(4),
                    usage: wgpu::BufferUsages::STORAGE
                        | wgpu::BufferUsages::COPY_DST
                        | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                })
            };
            self.recording = Some(Recording {
                size,
                msaa: c.msaa,
                edge_bits: buffer("tbdr edge bits", pixels.div_ceil(32) * 4),
                gbuffer: buffer(
                    "tbdr gbuffer capture",
                    pixels * u64::from(c.msaa) * u64::from(tbdr::CAPTURE_WORDS) * 4,
                ),
            });
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
                pass: self.name(),
                input,
            })
        };
        let c = &frame.config;
        let depth = resources.depth.ok_or(missing("pre-Z depth"))?;
        let gbuffer = resources.gbuffer.ok_or(missing("G-buffer"))?;
        let shadows = resources.shadows.clone().ok_or(missing("shadow atlas"))?;
        let mut hdr =
            graph.create_texture("hdr", TextureDesc::new_2d(c.width, c.height, HDR_FORMAT));
        let mut pass = graph.add_pass(self.name());
        read_gbuffer(&mut pass, depth, gbuffer, &shadows)
            .write_texture(&mut hdr, TextureAccess::StorageWrite);
        let program = self.program.clone();
        let (shade, capture) = (self.shade.clone(), self.capture.clone());
        let params = self.params.clone();
        let spheres = self.spheres.clone();
        let lights = std::sync::Arc::clone(&frame.lights);
        let recording = self
            .recording
            .as_ref()
            .filter(|_| self.record)
            .map(|r| (r.edge_bits.clone(), r.gbuffer.clone()));
        let (unused_edges, unused_capture) =
            (self.unused_edges.clone(), self.unused_capture.clone());
        // Edge bits: the recording's buffer when recording, the base pass's own otherwise.
        let edges = match (&recording, self.base_only) {
            (Some((e, _)), _) => Some(e.clone()),
            (None, true) => Some(self.edges.clone()),
            (None, false) => None,
        };
        if self.base_only {
            resources.deferred_edges = edges.clone();
        }
        let name = self.name();
        let (width, height, tile) = (c.width, c.height, c.tile);
        pass.execute(move |ctx| {
            let edge_bits = edges.as_ref().unwrap_or(&unused_edges);
            let captured = recording.as_ref().map_or(&unused_capture, |(_, g)| g);
            if edges.is_some() {
                ctx.encoder.clear_buffer(edge_bits, 0, None);
            }
            let buffers = KernelBuffers {
                params: &params,
                lights: &lights,
                spheres: &spheres,
                edge_bits,
                captured,
            };
            let out = ctx.texture(hdr).create_view(&Default::default());
            let views = GBufferViews::new(ctx, depth, gbuffer);
            let Some(group) = bind_group(ctx, &program, &buffers, &views, &out, &shadows) else {
                return;
            };
            let mut pass = ctx.encoder.begin_compute(name);
            pass.set_bind_group(0, &group, &[]);
            if recording.is_some() {
                pass.set_pipeline(&capture);
                let (x, y) = groups_8x8((width, height));
                pass.dispatch_workgroups(x, y, 1);
            }
            pass.set_pipeline(&shade);
            pass.dispatch_workgroups(width.div_ceil(tile), height.div_ceil(tile), 1);
        });
        resources.hdr = Some(hdr);
        resources.hdr_multisampled = None;
        Ok(())
    }
}

/// Declares that `pass` samples what the `tbdr` module's group 0 binds: the pre-Z depth, the
/// G-buffer and the shadow atlas.
pub(super) fn read_gbuffer<'p, 'g>(
    pass: &'p mut PassBuilder<'g>,
    depth: Handle<Texture>,
    gbuffer: GBufferHandles,
    shadows: &ShadowResources,
) -> &'p mut PassBuilder<'g> {
    pass.read_texture(depth, TextureAccess::Sampled)
        .read_texture(gbuffer.albedo, TextureAccess::Sampled)
        .read_texture(gbuffer.normals, TextureAccess::Sampled)
        .read_texture(gbuffer.radiance, TextureAccess::Sampled)
        .read_texture(gbuffer.view_depth, TextureAccess::Sampled)
        .read_texture(shadows.atlas, TextureAccess::Sampled)
}

/// The buffers of the `tbdr` module's group 0.
struct KernelBuffers<'a> {
    params: &'a wgpu::Buffer,
    lights: &'a crate::frame_data::LightSet,
    spheres: &'a wgpu::Buffer,
    edge_bits: &'a wgpu::Buffer,
    captured: &'a wgpu::Buffer,
}

/// Views of the pre-Z depth and the G-buffer's targets, made in a pass's recording, from which
/// the `tbdr_gbuffer` library's part of group 0 is built.
pub(super) struct GBufferViews {
    depth: wgpu::TextureView,
    albedo: wgpu::TextureView,
    normals: wgpu::TextureView,
    radiance: wgpu::TextureView,
    view_depth: wgpu::TextureView,
}

impl GBufferViews {
    pub(super) fn new(
        ctx: &crate::graph::PassContext<'_>,
        depth: Handle<Texture>,
        gbuffer: GBufferHandles,
    ) -> Self {
        let view = |h| ctx.texture(h).create_view(&Default::default());
        Self {
            depth: view(depth),
            albedo: view(gbuffer.albedo),
            normals: view(gbuffer.normals),
            radiance: view(gbuffer.radiance),
            view_depth: view(gbuffer.view_depth),
        }
    }

    /// The `tbdr_gbuffer` library's part (its generated builder), with parameters `params`. Each
    /// view is given for both spellings; the variant binds the one its MSAA count declares.
    pub(super) fn bindings<'a>(&'a self, params: &'a wgpu::Buffer) -> tbdr_gbuffer::Group0<'a> {
        tbdr_gbuffer::Group0 {
            params: params.as_entire_buffer_binding(),
            depth: Some(&self.depth),
            depth_ms: Some(&self.depth),
            albedo: Some(&self.albedo),
            albedo_ms: Some(&self.albedo),
            normals: Some(&self.normals),
            normals_ms: Some(&self.normals),
            radiance: Some(&self.radiance),
            radiance_ms: Some(&self.radiance),
            view_depth: Some(&self.view_depth),
            view_depth_ms: Some(&self.view_depth),
        }
    }
}

/// Group 0 of a `tbdr` variant `program`: its own buffers and HDR output `out`, the
/// `tbdr_gbuffer` library's part (parameters and the G-buffer), the lights' and the shadow
/// atlas's, through the module's generated builder; `None` after recording the error in `ctx`.
fn bind_group(
    ctx: &mut crate::graph::PassContext<'_>,
    program: &ShaderProgram,
    buffers: &KernelBuffers<'_>,
    gbuffer: &GBufferViews,
    out: &wgpu::TextureView,
    shadows: &ShadowResources,
) -> Option<wgpu::BindGroup> {
    let group = tbdr::Group0 {
        hdr_out: out,
        edge_bits: buffers.edge_bits.as_entire_buffer_binding(),
        capture: buffers.captured.as_entire_buffer_binding(),
        tbdr_gbuffer: gbuffer.bindings(buffers.params),
        light_set: buffers.lights.bindings(),
        light_spheres: light_spheres::Group0 {
            spheres: buffers.spheres.as_entire_buffer_binding(),
        },
        shadow_atlas: shadows.bindings(),
    }
    .bind_group(
        ctx.device,
        program.layout(tbdr::Group0::GROUP),
        program.variant,
        "tbdr",
    );
    ctx.bind(group)
}
