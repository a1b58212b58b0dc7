//! Texture formats several passes must agree on.

/// The linear HDR colour the forward pass writes and tonemapping reads.
pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The depth buffer of the pre-pass, read by culling and tested by forward shading.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
