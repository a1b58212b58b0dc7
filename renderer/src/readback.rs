//! Copies GPU textures and buffers back to the CPU, for tests, screenshots and debug views.
//!
//! These calls block until the GPU is done; they belong in tools and tests, not in a frame.

use crate::GpuError;

/// Reads a whole 4-bytes-per-texel 2D texture (for example `Rgba8Unorm`) into tightly packed rows.
pub fn read_texture_rgba8(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Vec<u8>, GpuError> {
    read_texture_level(device, queue, texture, 0)
}

/// Reads mip level `level` of a 4-bytes-per-texel 2D texture (`Rgba8Unorm`, `R32Float`, …)
/// into tightly packed rows.
pub fn read_texture_level(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    level: u32,
) -> Result<Vec<u8>, GpuError> {
    let size = texture
        .size()
        .mip_level_size(level, wgpu::TextureDimension::D2);
    let (width, height) = (size.width, size.height);
    let row_bytes = width * 4;
    let padded_row =
        row_bytes.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback texture"),
        size: u64::from(padded_row) * u64::from(height),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("readback texture"),
    });
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            mip_level: level,
            ..texture.as_image_copy()
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &staging,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded_row),
                rows_per_image: Some(height),
            },
        },
        size,
    );
    queue.submit([encoder.finish()]);
    let padded = map_and_copy(device, &staging)?;
    Ok(padded
        .chunks_exact(padded_row as usize)
        .flat_map(|row| &row[..row_bytes as usize])
        .copied()
        .collect())
}

/// Reads `buffer` (which needs `COPY_SRC`) as a slice of `T`.
pub fn read_buffer<T: bytemuck::Pod>(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    buffer: &wgpu::Buffer,
) -> Result<Vec<T>, GpuError> {
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback buffer"),
        size: buffer.size(),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("readback buffer"),
    });
    encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, buffer.size());
    queue.submit([encoder.finish()]);
    let bytes = map_and_copy(device, &staging)?;
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}

fn map_and_copy(device: &wgpu::Device, staging: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
    let slice = staging.slice(..);
    let (sender, receiver) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |result| {
        // The receiver lives until after the poll below; a send error cannot happen.
        let _ = sender.send(result);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(GpuError::Poll)?;
    match receiver.recv() {
        Ok(Ok(())) => {}
        Ok(Err(e)) => return Err(GpuError::Map(e)),
        Err(_) => return Err(GpuError::Map(wgpu::BufferAsyncError)),
    }
    let bytes = slice
        .get_mapped_range()
        .map_err(|e| GpuError::MapRange(e.to_string()))?
        .to_vec();
    staging.unmap();
    Ok(bytes)
}
