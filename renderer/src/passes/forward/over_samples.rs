//! Blended surfaces over the compute rasteriser's frame
//! ([`crate::frame_data::RendererConfig::reads_compute_samples`]): the forward pass draws them
//! with the `forward` module's `fs_forward_vis64` (the `msaa`, `blend`, `vis64` variant), which
//! reads the compute rasteriser's samples and writes, as its `sample_mask`, the samples where
//! the fragment is in front of the opaque surface. The pipeline has no depth test and the pass
//! no depth target, so that frame never writes a multisampled depth target for them.

use shaders_gen::visibility::vis_frame;

use super::bindings::FrameGroup;
use crate::frame_data::{ConfigError, FrameInputs, FrameResources, RenderError, VisibilitySamples};
use crate::graph::{Buffer, BufferAccess, Handle, PassBuilder, PassContext};
use crate::shader::ShaderProgram;

/// The uniform of the variant's `VIS` binding (`vis_frame::VisParams`, of which it reads only
/// the screen size, to find a pixel's samples in the buffer).
#[derive(Debug)]
pub(crate) struct OverSamples {
    params: wgpu::Buffer,
}

/// One frame's inputs of the blended variant: its uniform and the compute rasteriser's samples.
#[derive(Clone)]
pub(crate) struct FrameSamples {
    params: wgpu::Buffer,
    samples: Handle<Buffer>,
}

impl OverSamples {
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("blended over samples"),
            size: size_of::<vis_frame::VisParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self { params }
    }

    /// This frame's inputs, after writing the uniform; an error where the frame has no
    /// compute rasteriser's samples (the visibility pass did not run before).
    pub(crate) fn frame(
        &self,
        frame: &FrameInputs,
        resources: &FrameResources,
    ) -> Result<FrameSamples, RenderError> {
        let Some(VisibilitySamples::Buffer { samples }) =
            resources.visibility.as_ref().map(|v| v.samples)
        else {
            return Err(RenderError::Config(ConfigError::MissingInput {
                pass: "forward",
                input: "the compute rasteriser's samples",
            }));
        };
        // `vis_in_front` reads the screen size alone; the rest is the shading kernels'.
        let uniform = vis_frame::VisParams::new(
            glam::Mat4::IDENTITY,
            glam::Vec3::ZERO,
            0,
            frame.screen(),
            0,
            0,
            0,
            glam::UVec3::ZERO,
        );
        frame
            .gpu
            .queue()
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&uniform));
        Ok(FrameSamples {
            params: self.params.clone(),
            samples,
        })
    }
}

impl FrameSamples {
    /// Declares `pass`'s read of the samples.
    pub(crate) fn read_by(&self, pass: &mut PassBuilder<'_>) {
        pass.read_buffer(self.samples, BufferAccess::StorageRead);
    }

    /// Group 0 of `program` (the blended variant): `group`'s parts and the samples; `None`
    /// after recording the error in `ctx`.
    pub(crate) fn bind_group(
        &self,
        ctx: &mut PassContext<'_>,
        group: &FrameGroup,
        program: &ShaderProgram,
    ) -> Option<wgpu::BindGroup> {
        let samples = ctx.buffer(self.samples).clone();
        group.over_samples_bind_group(ctx, program, (&self.params, &samples))
    }
}
