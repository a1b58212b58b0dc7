//! Textures, buffers, bind groups, colour attachments and float readback for the draws of the
//! forward-shading tests.

use renderer::GpuContext;
use renderer::shader::ShaderProgram;
use wgpu::util::DeviceExt as _;

/// The binary16 bits of `x` (normal numbers and zero; mantissa truncated, exact for the values
/// the tests use: 0, 0.5, 1).
pub fn f16_bits(x: f32) -> u16 {
    if x == 0.0 {
        return 0;
    }
    let bits = x.to_bits();
    let sign = ((bits >> 16) & 0x8000) as u16;
    let exponent = ((bits >> 23) & 0xff) as i32 - 127 + 15;
    assert!((1..31).contains(&exponent), "{x} is not a normal f16");
    let mantissa = ((bits >> 13) & 0x3ff) as u16;
    sign | ((exponent as u16) << 10) | mantissa
}

pub fn program(gpu: &GpuContext, variant: &'static codegen::rt::Variant) -> ShaderProgram {
    ShaderProgram::new(gpu.device(), gpu.capabilities(), variant).expect("supported variant")
}

pub fn buffer(gpu: &GpuContext, bytes: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
    gpu.device()
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: bytes,
            usage,
        })
}

/// A storage buffer of `items`, at least 16 bytes (an empty binding is invalid).
pub fn storage<T: bytemuck::Pod>(gpu: &GpuContext, items: &[T]) -> wgpu::Buffer {
    let mut bytes = bytemuck::cast_slice::<T, u8>(items).to_vec();
    bytes.resize(bytes.len().max(16), 0);
    buffer(gpu, &bytes, wgpu::BufferUsages::STORAGE)
}

pub fn uniform<T: bytemuck::Pod>(gpu: &GpuContext, value: &T) -> wgpu::Buffer {
    buffer(gpu, bytemuck::bytes_of(value), wgpu::BufferUsages::UNIFORM)
}

pub fn texture(
    gpu: &GpuContext,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    gpu.device().create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// A texture filled with `data` (tightly packed rows).
pub fn texture_with(
    gpu: &GpuContext,
    size: (u32, u32),
    format: wgpu::TextureFormat,
    data: &[u8],
) -> wgpu::Texture {
    gpu.device().create_texture_with_data(
        gpu.queue(),
        &wgpu::TextureDescriptor {
            label: None,
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        data,
    )
}

/// A 1×1 `Rgba16Float` texture holding `rgba` (exact for 0, 0.5 and 1).
pub fn texel(gpu: &GpuContext, rgba: [f32; 4]) -> wgpu::Texture {
    let halves = rgba.map(f16_bits);
    texture_with(
        gpu,
        (1, 1),
        wgpu::TextureFormat::Rgba16Float,
        bytemuck::cast_slice(&halves),
    )
}

/// Reads a whole texture with `texel_bytes` bytes per texel into tightly packed rows.
pub fn read_texture(gpu: &GpuContext, texture: &wgpu::Texture, texel_bytes: u32) -> Vec<u8> {
    let (width, height) = (texture.width(), texture.height());
    let row = width * texel_bytes;
    let padded = row.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let staging = gpu.device().create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: u64::from(padded * height),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.device().create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &staging,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(height),
            },
        },
        texture.size(),
    );
    gpu.queue().submit([encoder.finish()]);
    let slice = staging.slice(..);
    slice.map_async(wgpu::MapMode::Read, |r| r.expect("map"));
    gpu.device()
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("poll");
    let data = slice.get_mapped_range().expect("mapped");
    data.chunks_exact(padded as usize)
        .flat_map(|r| &r[..row as usize])
        .copied()
        .collect()
}

pub(super) fn bind_group(
    gpu: &GpuContext,
    program: &ShaderProgram,
    group: usize,
    resources: Vec<(u32, wgpu::BindingResource<'_>)>,
) -> wgpu::BindGroup {
    let entries: Vec<_> = resources
        .into_iter()
        .map(|(binding, resource)| wgpu::BindGroupEntry { binding, resource })
        .collect();
    gpu.device().create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &program.bind_group_layouts[group],
        entries: &entries,
    })
}

/// A colour attachment cleared to transparent black and stored.
pub(super) fn cleared(
    view: &wgpu::TextureView,
) -> [Option<wgpu::RenderPassColorAttachment<'_>>; 1] {
    [Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
            store: wgpu::StoreOp::Store,
        },
    })]
}

pub(super) fn color_pass<'a>(
    attachments: &'a [Option<wgpu::RenderPassColorAttachment<'a>>],
) -> wgpu::RenderPassDescriptor<'a> {
    wgpu::RenderPassDescriptor {
        label: None,
        color_attachments: attachments,
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    }
}
