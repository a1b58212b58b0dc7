//! What a pass's recording function gets: the encoder, the device and the GPU objects behind its
//! handles. Below the builder (which stores recording functions) and execution (which calls them).

use super::resource::{Buffer, Handle, Texture};

/// A physical GPU object behind a resource: a pool transient or a bound import.
#[derive(Debug, Clone)]
pub(crate) enum PoolObject {
    Texture(wgpu::Texture),
    Buffer(wgpu::Buffer),
}

/// What a pass's recording function gets: the encoder and its resources' GPU objects.
#[derive(Debug)]
pub struct PassContext<'a> {
    pub encoder: &'a mut wgpu::CommandEncoder,
    pub device: &'a wgpu::Device,
    objects: &'a [Option<PoolObject>],
}

impl<'a> PassContext<'a> {
    pub(super) fn new(
        encoder: &'a mut wgpu::CommandEncoder,
        device: &'a wgpu::Device,
        objects: &'a [Option<PoolObject>],
    ) -> Self {
        Self {
            encoder,
            device,
            objects,
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
