//! Texture formats several passes must agree on.

/// The linear HDR colour the forward pass writes and tonemapping reads.
pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The depth buffer of the pre-pass, read by culling and tested by forward shading.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The G-buffer of the deferred paths (`forward::GBufferOut`): albedo and metalness (sRGB
/// albedo, 4 bytes), the octahedral shading and geometric normals (four 16-bit floats), base
/// radiance and roughness (four 16-bit floats), the view depth (a 32-bit float): 24 bytes per
/// sample, besides the pre-Z depth.
pub const GBUFFER_FORMATS: [wgpu::TextureFormat; 4] = [
    wgpu::TextureFormat::Rgba8UnormSrgb,
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::R32Float,
];

/// The visibility buffer of the visibility path: a triangle ID per sample, 4 bytes, besides
/// the depth.
pub const VISIBILITY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
