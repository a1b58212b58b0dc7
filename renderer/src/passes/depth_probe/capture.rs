//! Frame capture for tools: one frame's depth at a grid of probe points, its light-grid counts,
//! camera and light spheres, read back so a tool can measure the frame (the benchmark's cull
//! efficiency: lights listed ÷ lights that reach the surface).
//!
//! `Renderer::capture_next_frame` asks for it; the next frame's depth-probe pass probes the
//! depth and copies the light grid in the same submission; `Renderer::take_capture` reads both
//! back (blocking).

use crate::frame_data::ConfigError;
use glam::{UVec2, Vec3};
use shaders_gen::inspect::depth_probe;
use wgpu::util::DeviceExt as _;

use crate::GpuContext;
use crate::culling::depth::{DepthBuffer, Efficiency, standard_sample_offset};
use crate::culling::{CullCamera, LightSphere, Method};
use crate::readback;
use crate::shader::ShaderProgram;

/// The probe kernel of one MSAA count, built once per renderer.
#[derive(Debug)]
pub struct ProbePipeline {
    pub program: ShaderProgram,
    pub pipeline: wgpu::ComputePipeline,
}

impl ProbePipeline {
    pub fn new(gpu: &GpuContext, msaa: u32) -> Result<Self, crate::frame_data::RenderError> {
        let key = depth_probe::VariantKey {
            msaa: depth_probe::Msaa::from_value(msaa)
                .ok_or_else(|| ConfigError::shader_sample_count(msaa))?,
        };
        let program = gpu.program(depth_probe::variant(key))?;
        let pipeline = program.compute_pipeline(gpu.device(), "probe")?;
        Ok(Self { program, pipeline })
    }
}

/// GPU state of one capture: the kernel, its parameters and the output buffer.
#[derive(Debug)]
pub struct ProbeGpu {
    pub kernel: std::sync::Arc<ProbePipeline>,
    pub params: wgpu::Buffer,
    pub output: wgpu::Buffer,
    /// Probes across and down.
    pub grid: UVec2,
}

impl ProbeGpu {
    pub fn new(
        device: &wgpu::Device,
        kernel: &std::sync::Arc<ProbePipeline>,
        screen: UVec2,
        stride: u32,
    ) -> Self {
        let grid = UVec2::new(screen.x.div_ceil(stride), screen.y.div_ceil(stride));
        let params = depth_probe::ProbeParams::new(screen, grid, stride);
        Self {
            kernel: std::sync::Arc::clone(kernel),
            params: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("depth probe params"),
                contents: bytemuck::bytes_of(&params),
                usage: wgpu::BufferUsages::UNIFORM,
            }),
            output: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("depth probes"),
                size: u64::from(grid.x * grid.y) * 4,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            grid,
        }
    }
}

/// A capture recorded into a frame, waiting to be read back.
#[derive(Debug)]
pub struct PendingCapture {
    pub probe: std::sync::Arc<ProbeGpu>,
    pub stride: u32,
    pub msaa: u32,
    pub camera: CullCamera,
    pub lights: Vec<LightSphere>,
    pub method: Option<Method>,
    /// A copy of the light grid made right after culling, in the same submission.
    pub grid_copy: Option<wgpu::Buffer>,
}

impl PendingCapture {
    pub fn read_back(self, gpu: &GpuContext) -> Result<FrameCapture, crate::GpuError> {
        let probes = readback::read_buffer::<f32>(gpu.device(), gpu.queue(), &self.probe.output)?;
        let cell_counts = match &self.grid_copy {
            Some(b) => Some(
                readback::read_buffer::<UVec2>(gpu.device(), gpu.queue(), b)?
                    .iter()
                    .map(|c| c.y)
                    .collect(),
            ),
            None => None,
        };
        Ok(FrameCapture {
            camera: self.camera,
            msaa: self.msaa,
            stride: self.stride,
            grid: self.probe.grid,
            probes,
            lights: self.lights,
            method: self.method,
            cell_counts,
        })
    }
}

/// What a captured frame holds.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameCapture {
    /// The frame's camera as culling saw it (size included).
    pub camera: CullCamera,
    /// Samples per pixel of the captured depth.
    pub msaa: u32,
    /// Pixels between probes.
    pub stride: u32,
    /// Probes across and down.
    pub grid: UVec2,
    /// Depth at each probe, row by row (wgpu convention, 1.0 = sky).
    pub probes: Vec<f32>,
    /// Light bounding spheres in world space, in item order.
    pub lights: Vec<LightSphere>,
    /// The culling method of the frame (none on the naive paths).
    pub method: Option<Method>,
    /// Lights listed per cell (tile or froxel), from the frame's light grid.
    pub cell_counts: Option<Vec<u32>>,
}

/// One probe that hit a surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceProbe {
    /// Pixel column.
    pub x: u32,
    /// Pixel row.
    pub y: u32,
    /// View-space position of the sample.
    pub position: Vec3,
}

impl FrameCapture {
    /// Pixel and sample of probe `(i, j)`, as the depth-probe kernel picks them.
    pub fn probe_sample(&self, i: u32, j: u32) -> (u32, u32, u32) {
        let half = self.stride / 2;
        let x = (i * self.stride + half).min(self.camera.width - 1);
        let y = (j * self.stride + half).min(self.camera.height - 1);
        (x, y, (i + j) % self.msaa)
    }

    /// The probes that hold a surface, with their view-space positions.
    pub fn surface_probes(&self) -> Vec<SurfaceProbe> {
        let mut out = Vec::new();
        for j in 0..self.grid.y {
            for i in 0..self.grid.x {
                let depth = self.probes[(j * self.grid.x + i) as usize];
                if !DepthBuffer::is_surface(depth) {
                    continue;
                }
                let (x, y, s) = self.probe_sample(i, j);
                let (ox, oy) = standard_sample_offset(self.msaa, s);
                let (nx, ny) = self.camera.pixel_to_ndc(x as f32 + ox, y as f32 + oy);
                out.push(SurfaceProbe {
                    x,
                    y,
                    position: self.camera.unproject(nx, ny, depth),
                });
            }
        }
        out
    }

    /// For each surface probe, how many lights' spheres contain it (brute force, independent of
    /// any culling code). The same for every method of a frame, so callers may reuse it.
    pub fn lights_reaching(&self, surface: &[SurfaceProbe]) -> Vec<u32> {
        let view: Vec<LightSphere> = self
            .lights
            .iter()
            .map(|l| l.to_view(self.camera.view))
            .collect();
        surface
            .iter()
            .map(|p| {
                view.iter()
                    .filter(|l| l.center.distance_squared(p.position) <= l.radius * l.radius)
                    .count() as u32
            })
            .collect()
    }

    /// Lights listed for the probes' cells against lights reaching them (`reaching` from
    /// [`Self::lights_reaching`] on the same `surface`); `None` without culling.
    pub fn cull_efficiency(
        &self,
        surface: &[SurfaceProbe],
        reaching: &[u32],
    ) -> Option<Efficiency> {
        let (method, counts) = (self.method?, self.cell_counts.as_ref()?);
        let (w, h) = (self.camera.width, self.camera.height);
        let listed = surface
            .iter()
            .map(|p| u64::from(counts[method.cell_of(w, h, p.x, p.y, -p.position.z)]))
            .sum();
        Some(Efficiency {
            listed,
            reaching: reaching.iter().map(|&r| u64::from(r)).sum(),
        })
    }
}
