//! What a builder's fields hold, as one type: a buffer range, a texture view or a sampler.

/// One resource given to a builder.
#[derive(Debug, Clone)]
pub enum Resource<'a> {
    /// A uniform or storage buffer range.
    Buffer(wgpu::BufferBinding<'a>),
    /// A sampled or storage texture view.
    Texture(&'a wgpu::TextureView),
    /// A sampler.
    Sampler(&'a wgpu::Sampler),
}

impl<'a> From<wgpu::BufferBinding<'a>> for Resource<'a> {
    fn from(b: wgpu::BufferBinding<'a>) -> Self {
        Resource::Buffer(b)
    }
}

impl<'a> From<&'a wgpu::TextureView> for Resource<'a> {
    fn from(v: &'a wgpu::TextureView) -> Self {
        Resource::Texture(v)
    }
}

impl<'a> From<&'a wgpu::Sampler> for Resource<'a> {
    fn from(s: &'a wgpu::Sampler) -> Self {
        Resource::Sampler(s)
    }
}

/// A resource as a bind group held it, owned: what [`crate::Resources::snapshot`] keeps so a
/// tool can read back, after the GPU ran, exactly what a dispatch or draw was given.
#[derive(Debug, Clone)]
pub enum BoundResource {
    /// A buffer range: `size` `None` runs to the buffer's end.
    Buffer {
        buffer: wgpu::Buffer,
        offset: u64,
        size: Option<std::num::NonZeroU64>,
    },
    /// The texture a view was made of. wgpu does not report a view's format, layers or mip
    /// levels: a reader that needs them (an sRGB view of a linear texture) knows them.
    Texture(wgpu::Texture),
    /// A sampler (its settings are not readable from wgpu).
    Sampler(wgpu::Sampler),
}

impl From<&Resource<'_>> for BoundResource {
    fn from(resource: &Resource<'_>) -> Self {
        match resource {
            Resource::Buffer(b) => BoundResource::Buffer {
                buffer: b.buffer.clone(),
                offset: b.offset,
                size: b.size,
            },
            Resource::Texture(v) => BoundResource::Texture(v.texture().clone()),
            Resource::Sampler(s) => BoundResource::Sampler((*s).clone()),
        }
    }
}
