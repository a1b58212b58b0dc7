//! Virtual resources: descriptors, typed versioned handles, and the ways a pass may access them.

use std::marker::PhantomData;

/// Marker for texture handles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Texture {}
/// Marker for buffer handles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Buffer {}

/// A versioned reference to a virtual resource of one graph.
#[derive(Debug, PartialEq, Eq)]
pub struct Handle<T> {
    pub(crate) graph: u64,
    pub(crate) index: usize,
    pub(crate) version: u32,
    _kind: PhantomData<T>,
}

impl<T> Clone for Handle<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for Handle<T> {}

impl<T> Handle<T> {
    /// Which write of the resource this handle names (0: none yet; imports start at 1).
    pub fn version(self) -> u32 {
        self.version
    }

    pub(crate) fn new(graph: u64, index: usize) -> Self {
        Self {
            graph,
            index,
            version: 0,
            _kind: PhantomData,
        }
    }
}

/// A 2D texture the graph creates (transient) or is given (imported).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TextureDesc {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Texel format.
    pub format: wgpu::TextureFormat,
    /// MSAA samples (1: not multisampled; above 1 the texture can only be an attachment).
    pub sample_count: u32,
    /// Array layers (1 for a plain 2D texture).
    pub layers: u32,
}

impl TextureDesc {
    /// A single-sampled, single-layer 2D texture.
    pub fn new_2d(width: u32, height: u32, format: wgpu::TextureFormat) -> Self {
        Self {
            width,
            height,
            format,
            sample_count: 1,
            layers: 1,
        }
    }

    /// This descriptor with `sample_count` MSAA samples.
    #[must_use]
    pub fn with_samples(mut self, sample_count: u32) -> Self {
        self.sample_count = sample_count;
        self
    }

    /// A texture of this description (one mip level) with `usage`.
    pub fn create(
        &self,
        device: &wgpu::Device,
        label: &str,
        usage: wgpu::TextureUsages,
    ) -> wgpu::Texture {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: self.width,
                height: self.height,
                depth_or_array_layers: self.layers,
            },
            mip_level_count: 1,
            sample_count: self.sample_count,
            dimension: wgpu::TextureDimension::D2,
            format: self.format,
            usage,
            view_formats: &[],
        })
    }

    /// Whether `texture` is of this description.
    pub fn describes(&self, texture: &wgpu::Texture) -> bool {
        let size = (
            texture.width(),
            texture.height(),
            texture.depth_or_array_layers(),
        );
        size == (self.width, self.height, self.layers)
            && (texture.sample_count(), texture.format()) == (self.sample_count, self.format)
    }
}

/// A buffer the graph creates (transient) or is given (imported).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct BufferDesc {
    /// Size in bytes.
    pub size: u64,
}

/// How a pass touches a texture.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TextureAccess {
    /// Sampled or loaded in a shader.
    Sampled,
    /// Bound as a storage texture and written.
    StorageWrite,
    /// Rendered to as a colour attachment (or resolve target).
    ColorAttachment,
    /// Depth attachment, depth writes on.
    DepthWrite,
    /// Depth attachment, depth test only.
    DepthRead,
    /// Source of a copy.
    CopySrc,
    /// Destination of a copy.
    CopyDst,
}

impl TextureAccess {
    /// Whether this access modifies the texture (storage write, colour or depth write, copy
    /// destination).
    pub fn is_write(self) -> bool {
        matches!(
            self,
            Self::StorageWrite | Self::ColorAttachment | Self::DepthWrite | Self::CopyDst
        )
    }

    /// The texture usage this access needs; the graph creates transients with the union.
    pub fn usage(self) -> wgpu::TextureUsages {
        use wgpu::TextureUsages as U;
        match self {
            Self::Sampled => U::TEXTURE_BINDING,
            Self::StorageWrite => U::STORAGE_BINDING,
            Self::ColorAttachment | Self::DepthWrite | Self::DepthRead => U::RENDER_ATTACHMENT,
            Self::CopySrc => U::COPY_SRC,
            Self::CopyDst => U::COPY_DST,
        }
    }
}

/// How a pass touches a buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BufferAccess {
    /// Bound as a uniform buffer.
    Uniform,
    /// Bound as a read-only storage buffer.
    StorageRead,
    /// Bound as a storage buffer and written.
    StorageWrite,
    /// Arguments of an indirect draw or dispatch.
    Indirect,
    /// Bound as a vertex buffer.
    Vertex,
    /// Bound as an index buffer.
    Index,
    /// Source of a copy.
    CopySrc,
    /// Destination of a copy.
    CopyDst,
}

impl BufferAccess {
    /// Whether this access modifies the buffer (storage write or copy destination).
    pub fn is_write(self) -> bool {
        matches!(self, Self::StorageWrite | Self::CopyDst)
    }

    /// The buffer usage this access needs; the graph creates transients with the union.
    pub fn usage(self) -> wgpu::BufferUsages {
        use wgpu::BufferUsages as U;
        match self {
            Self::Uniform => U::UNIFORM,
            Self::StorageRead | Self::StorageWrite => U::STORAGE,
            Self::Indirect => U::INDIRECT,
            Self::Vertex => U::VERTEX,
            Self::Index => U::INDEX,
            Self::CopySrc => U::COPY_SRC,
            Self::CopyDst => U::COPY_DST,
        }
    }
}

/// What passes may do to an imported resource.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ImportAccess {
    /// Passes may only read it (for example light data uploaded by the host).
    ReadOnly,
    /// Passes may write it; a pass that does is kept, since the result is seen outside.
    ReadWrite,
}
