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

/// Whether a target texture stored as `stored` takes frames of the output format `output`:
/// the same format, or, for an sRGB output, its linear twin (`Rgba8Unorm` for
/// `Rgba8UnormSrgb`) with the sRGB format among the texture's view formats. A target stored
/// linear can be a storage image, which an sRGB format cannot be, so the compute tonemap writes
/// it without a copy (see [`crate::frame::create_target`]).
pub(crate) fn target_takes(output: wgpu::TextureFormat, stored: wgpu::TextureFormat) -> bool {
    stored == output || (output.is_srgb() && stored == output.remove_srgb_suffix())
}

/// A view of the frame's target in the output format `output`, to draw into: the texture's own
/// format, or the sRGB view of a target stored as its linear twin ([`target_takes`]).
pub(crate) fn output_view(
    target: &wgpu::Texture,
    output: wgpu::TextureFormat,
) -> wgpu::TextureView {
    target.create_view(&wgpu::TextureViewDescriptor {
        label: Some("frame output"),
        format: Some(output),
        // An sRGB view cannot carry the linear texture's storage usage.
        usage: Some(wgpu::TextureUsages::RENDER_ATTACHMENT),
        ..Default::default()
    })
}
