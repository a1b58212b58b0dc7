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
