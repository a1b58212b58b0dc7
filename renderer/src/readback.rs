//! Copies GPU textures and buffers back to the CPU, for tests, screenshots and debug views.
//!
//! Each reader has two forms. The `_async` one is what a browser page uses: there it never
//! blocks, the copy's mapping completing from the page's event loop; on native backends the
//! future polls the device until the copy is done, blocking its thread meanwhile. The plain
//! one blocks until the GPU is done (native only: in a browser it returns
//! [`GpuError::BlockingInBrowser`]). Both belong in tools and tests, not in a
//! frame.

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
    block_on(
        "read_texture_level",
        read_texture_level_async(device, queue, texture, level),
    )
}

/// [`read_texture_rgba8`] without blocking (see the module's documentation).
pub async fn read_texture_rgba8_async(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Vec<u8>, GpuError> {
    read_texture_level_async(device, queue, texture, 0).await
}

/// [`read_texture_level`] without blocking (see the module's documentation).
pub async fn read_texture_level_async(
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
    let padded = map_and_copy(device, &staging).await?;
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
    block_on("read_buffer", read_buffer_async(device, queue, buffer))
}

/// [`read_buffer`] without blocking (see the module's documentation).
pub async fn read_buffer_async<T: bytemuck::Pod>(
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
    let bytes = map_and_copy(device, &staging).await?;
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}

/// Runs a readback's future to its end on this thread: native only, where polling the device
/// inside the future completes it.
#[cfg(not(target_arch = "wasm32"))]
fn block_on<T>(
    _name: &'static str,
    future: impl Future<Output = Result<T, GpuError>>,
) -> Result<T, GpuError> {
    pollster::block_on(future)
}

/// In a browser nothing may wait for the GPU: the blocking readers refuse, naming themselves.
#[cfg(target_arch = "wasm32")]
fn block_on<T>(
    name: &'static str,
    _future: impl Future<Output = Result<T, GpuError>>,
) -> Result<T, GpuError> {
    Err(GpuError::BlockingInBrowser(name))
}

/// Maps `staging` (its copy already submitted) and returns its bytes.
async fn map_and_copy(device: &wgpu::Device, staging: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
    let slice = staging.slice(..);
    let (sender, mapped) = futures_channel::oneshot::channel();
    slice.map_async(wgpu::MapMode::Read, move |result| {
        // The receiver is awaited below; a send error cannot happen.
        let _ = sender.send(result);
    });
    // Native backends call back from a poll; a browser calls back from its event loop, and its
    // poll returns at once.
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(GpuError::Poll)?;
    match mapped.await {
        Ok(Ok(())) => {}
        Ok(Err(e)) => return Err(GpuError::Map(e)),
        Err(futures_channel::oneshot::Canceled) => {
            return Err(GpuError::Map(wgpu::BufferAsyncError));
        }
    }
    let bytes = slice
        .get_mapped_range()
        .map_err(|e| GpuError::MapRange(e.to_string()))?
        .to_vec();
    staging.unmap();
    Ok(bytes)
}
