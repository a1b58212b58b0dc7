//! A full-screen test-pattern frame: the smallest real render pass, with GPU timing.
//!
//! `cargo xtask demo` shows it until the scene renderer replaces it, and the GPU tests check its
//! pixels against a CPU recomputation. The shaders come from `shaders_gen::bootstrap`.

use shaders_gen::bootstrap::test_pattern::{self, PatternParams};
use wgpu::util::DeviceExt as _;

use crate::shader::{ShaderProgram, VariantError};
use crate::{GpuContext, GpuError, readback};

/// Colour format of the pattern target: linear 8-bit, so a CPU can predict every byte.
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// A rendered pattern frame.
#[derive(Debug, Clone)]
pub struct PatternFrame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Tightly packed RGBA8 rows, top row first.
    pub rgba: Vec<u8>,
    /// GPU time of the render pass, when the device has timestamp queries.
    pub gpu_time: Option<std::time::Duration>,
}

/// Parameters of the pattern for a `width`×`height` target.
pub fn params(width: u32, height: u32) -> PatternParams {
    let radius = width.min(height) * 3 / 10;
    let thickness = (width.min(height) / 40).max(1);
    PatternParams::new(
        glam::UVec2::new(width, height),
        32,
        glam::UVec2::new(radius * radius, (radius + thickness) * (radius + thickness)),
    )
}

/// Why the pattern frame could not be rendered.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PatternError {
    /// Timing, readback or waiting for the GPU failed.
    #[error(transparent)]
    Gpu(#[from] GpuError),
    /// The pattern's shader variant cannot run on this device.
    #[error(transparent)]
    Variant(#[from] VariantError),
    /// The pattern's bind group could not be built.
    #[error(transparent)]
    Bind(#[from] shader_bind::BindError),
}

/// Renders the pattern into a new `width`×`height` texture and reads it back.
pub fn render(gpu: &GpuContext, width: u32, height: u32) -> Result<PatternFrame, PatternError> {
    let device = gpu.device();
    let variant = test_pattern::variant(test_pattern::VariantKey::ALL[0]);
    let program = gpu.program(variant)?;
    let vs = program.entry(codegen::rt::Stage::Vertex, "vs_fullscreen")?;
    let fs = program.entry(codegen::rt::Stage::Fragment, "fs_pattern")?;
    let pipeline = pattern_pipeline(device, &program, vs, fs);
    let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("test pattern params"),
        contents: bytemuck::bytes_of(&params(width, height)),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let bind_group = test_pattern::Group0 {
        params: uniform.as_entire_buffer_binding(),
    }
    .bind_group(device, program.layout(0), variant, "test pattern")?;
    let target = pattern_target(device, width, height);
    let view = target.create_view(&Default::default());

    let mut profiler = wgpu_profiler::GpuProfiler::new(device, Default::default())
        .map_err(|e| GpuError::Profiler(e.to_string()))?;
    let mut encoder = device.create_command_encoder(&Default::default());
    let query = profiler.begin_pass_query("test pattern", &mut encoder);
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("test pattern"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: query.render_pass_timestamp_writes(),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.draw(0..3, 0..1);
    }
    profiler.end_query(&mut encoder, query);
    profiler.resolve_queries(&mut encoder);
    gpu.queue().submit([encoder.finish()]);
    profiler
        .end_frame()
        .map_err(|e| GpuError::Profiler(e.to_string()))?;
    let rgba = readback::read_texture_rgba8(device, gpu.queue(), &target)?;
    gpu.wait_idle()?;
    let gpu_time = profiler
        .process_finished_frame(gpu.queue().get_timestamp_period())
        .and_then(|scopes| scopes.into_iter().find_map(|s| s.time))
        .map(|t| std::time::Duration::from_secs_f64(t.end - t.start));
    Ok(PatternFrame {
        width,
        height,
        rgba,
        gpu_time,
    })
}

/// The pattern's full-screen pipeline into one [`FORMAT`] target.
fn pattern_pipeline(
    device: &wgpu::Device,
    program: &ShaderProgram,
    vs: &str,
    fs: &str,
) -> wgpu::RenderPipeline {
    let module = &program.module;
    program.render_pipeline(
        device,
        &wgpu::RenderPipelineDescriptor {
            label: Some("test pattern"),
            layout: Some(&program.pipeline_layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some(vs),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module,
                entry_point: Some(fs),
                compilation_options: Default::default(),
                targets: &[Some(FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        },
    )
}

/// A `width`×`height` [`FORMAT`] texture to render into and read back.
fn pattern_target(device: &wgpu::Device, width: u32, height: u32) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("test pattern target"),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}
