//! What a pass's recording function gets: the encoder, the device and the GPU objects behind its
//! handles. Below the builder (which stores recording functions) and execution (which calls them).

use super::encoder::PassEncoder;
use super::resource::{Buffer, Handle, Texture};

/// A physical GPU object behind a resource: a pool transient or a bound import.
#[derive(Debug, Clone)]
pub(crate) enum PoolObject {
    Texture(wgpu::Texture),
    Buffer(wgpu::Buffer),
}

/// What a pass's recording function gets: the encoder and its resources' GPU objects.
pub struct PassContext<'a> {
    /// The frame's encoder, inside this pass's profiler scope. Compute and render passes begin
    /// through it ([`PassEncoder::begin_compute`], [`PassEncoder::begin_render`]) so that they
    /// are timed on devices that time only whole passes.
    pub encoder: PassEncoder<'a>,
    /// The device, for bind groups and other per-pass objects.
    pub device: &'a wgpu::Device,
    objects: &'a [Option<PoolObject>],
    /// The first bind group this pass could not build ([`PassContext::bind`]).
    pub(super) bind_error: Option<shader_bind::BindError>,
}

impl std::fmt::Debug for PassContext<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PassContext")
            .field("encoder", &self.encoder)
            .field("device", &self.device)
            .field("objects", &self.objects)
            .finish_non_exhaustive()
    }
}

impl<'a> PassContext<'a> {
    pub(super) fn new(
        encoder: PassEncoder<'a>,
        device: &'a wgpu::Device,
        objects: &'a [Option<PoolObject>],
    ) -> Self {
        Self {
            encoder,
            device,
            objects,
            bind_error: None,
        }
    }

    /// What a generated bind-group builder built (a bind group, or a recording that binds
    /// some), or `None` after keeping its error: the pass then records nothing more, and
    /// executing the graph fails with [`super::GraphError::Bind`] naming the pass and the
    /// binding.
    pub fn bind<T>(&mut self, built: Result<T, shader_bind::BindError>) -> Option<T> {
        match built {
            Ok(group) => Some(group),
            Err(e) => {
                self.bind_error.get_or_insert(e);
                None
            }
        }
    }

    /// The texture behind `handle`.
    pub fn texture(&self, handle: Handle<Texture>) -> &wgpu::Texture {
        match &self.objects[handle.index] {
            Some(PoolObject::Texture(t)) => t,
            // Compilation and binding checked every resource a kept pass uses.
            _ => unreachable!("texture handle without a texture"),
        }
    }

    /// The buffer behind `handle`.
    pub fn buffer(&self, handle: Handle<Buffer>) -> &wgpu::Buffer {
        match &self.objects[handle.index] {
            Some(PoolObject::Buffer(b)) => b,
            _ => unreachable!("buffer handle without a buffer"),
        }
    }
}
