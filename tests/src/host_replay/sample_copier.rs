//! Every sample of a multisampled `u32` or depth texture copied into a storage buffer
//! (`shaders_gen`'s `sample_copy`), since a multisampled texture cannot be copied to a buffer.

use renderer::GpuContext;
use renderer::frame::{ConfigError, RenderError};
use renderer::graph::PassContext;
use renderer::shader::ShaderProgram;
use shaders_gen::inspect::sample_copy;

/// A texture's size and format as copied: `samples > 1` only for a `sample_copy` copy.
#[derive(Debug, Clone, Copy)]
pub(super) struct TextureShape {
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) layers: u32,
    pub(super) samples: u32,
    pub(super) format: wgpu::TextureFormat,
}

/// `sample_copy` for one sample count: every sample of a multisampled `u32` or depth texture
/// into a storage buffer.
#[derive(Debug)]
pub(super) struct SampleCopier {
    /// The `R32Uint` copy, then the `Depth32Float` one.
    kernels: [(ShaderProgram, wgpu::ComputePipeline); 2],
}

impl SampleCopier {
    pub(super) fn new(gpu: &GpuContext, msaa: u32) -> Result<Self, RenderError> {
        let msaa = sample_copy::Msaa::from_value(msaa).ok_or_else(|| {
            RenderError::Config(ConfigError::SampleCount {
                asked: msaa,
                supported: sample_copy::Msaa::ALL.iter().map(|m| m.value()).collect(),
            })
        })?;
        let kernel = |depth| -> Result<_, RenderError> {
            let variant = sample_copy::variant(sample_copy::VariantKey { msaa, depth });
            let program = ShaderProgram::new(gpu.device(), gpu.capabilities(), variant)?;
            Ok((program.compute_pipeline(gpu.device(), "copy")?, program))
        };
        let ((ids_pipeline, ids), (depth_pipeline, depth)) = (kernel(false)?, kernel(true)?);
        Ok(Self {
            kernels: [(ids, ids_pipeline), (depth, depth_pipeline)],
        })
    }

    pub(super) fn copy(
        &self,
        ctx: &mut PassContext<'_>,
        name: &str,
        texture: &wgpu::Texture,
        shape: TextureShape,
    ) -> Result<wgpu::Buffer, String> {
        let (program, pipeline) = match shape.format {
            wgpu::TextureFormat::R32Uint => &self.kernels[0],
            wgpu::TextureFormat::Depth32Float => &self.kernels[1],
            other => return Err(format!("`{name}`: multisampled {other:?}")),
        };
        let size = 4 * u64::from(shape.width * shape.height * shape.samples);
        let copy = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(name),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let view = texture.create_view(&Default::default());
        let is_depth = shape.format == wgpu::TextureFormat::Depth32Float;
        let group = sample_copy::Group0 {
            samples: copy.as_entire_buffer_binding(),
            source: (!is_depth).then_some(&view),
            source_depth: is_depth.then_some(&view),
        }
        .bind_group(
            ctx.device,
            program.layout(sample_copy::Group0::GROUP),
            program.variant,
            "sample copy",
        )
        .map_err(|e| e.to_string())?;
        let mut pass = ctx
            .encoder
            .begin_compute_pass(&wgpu::ComputePassDescriptor::default());
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups(shape.width.div_ceil(8), shape.height.div_ceil(8), 1);
        Ok(copy)
    }
}
