//! What the host-interpreter harnesses of the shading kernels (`tbdr_interp`,
//! `particle_light_interp`) share: copies of a frame's GPU data taken by a probe pass inside the
//! frame, read back afterwards, and the shadow atlas handed to a host dispatch as the renderer
//! binds it.

use codegen::interp::{Address, Compare, Dispatch, EvalError, HostSampler, HostTexture};
use renderer::GpuContext;
use renderer::frame_data::ShadowResources;
use renderer::graph::PassContext;
use renderer::readback::read_buffer;

/// Bytes per `Depth32Float` texel (the shadow atlas).
const DEPTH_TEXEL: u32 = 4;

/// Bytes per row of a texture copy: `bytes` rounded up to wgpu's row alignment.
pub fn padded_row(bytes: u32) -> u32 {
    bytes.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT
}

/// A buffer a probe copies into (and reads back from).
pub fn copy_target(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(4),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// Reads `buffer` back as bytes.
pub fn read_bytes(gpu: &GpuContext, buffer: &wgpu::Buffer) -> Result<Vec<u8>, String> {
    read_buffer::<u8>(gpu.device(), gpu.queue(), buffer).map_err(|e| e.to_string())
}

/// `rows` rows of `row_bytes` bytes each from a copy whose rows are padded to the alignment.
pub fn unpad(bytes: &[u8], row_bytes: u32, rows: u32) -> Vec<u8> {
    let mut out = Vec::with_capacity((row_bytes * rows) as usize);
    for row in bytes
        .chunks_exact(padded_row(row_bytes) as usize)
        .take(rows as usize)
    {
        out.extend_from_slice(&row[..row_bytes as usize]);
    }
    out
}

/// The shadow views and the shadow atlas's depth of a frame, copied by a probe pass.
#[derive(Debug, Clone)]
pub struct ShadowCopies {
    side: u32,
    views: wgpu::Buffer,
    atlas: wgpu::Buffer,
}

/// The shadow inputs as read back: `SHADOW_VIEWS`' bytes and the atlas's depth, row-major.
#[derive(Debug, Clone)]
pub struct ShadowInputs {
    pub views: Vec<u8>,
    pub side: u32,
    pub atlas: Vec<f32>,
}

impl ShadowCopies {
    /// Copy targets for `shadows`, whose atlas is `side` texels square.
    pub fn new(device: &wgpu::Device, shadows: &ShadowResources, side: u32) -> Self {
        Self {
            side,
            views: copy_target(device, "probe shadow views", shadows.views.size()),
            atlas: copy_target(
                device,
                "probe shadow atlas",
                u64::from(padded_row(side * DEPTH_TEXEL)) * u64::from(side),
            ),
        }
    }

    /// Records the copies; the probe pass must read `shadows.atlas` as a copy source.
    pub fn record(&self, ctx: &mut PassContext<'_>, shadows: &ShadowResources) {
        let atlas = ctx.texture(shadows.atlas).clone();
        ctx.encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &atlas,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::DepthOnly,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &self.atlas,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded_row(self.side * DEPTH_TEXEL)),
                    rows_per_image: Some(self.side),
                },
            },
            atlas.size(),
        );
        ctx.encoder
            .copy_buffer_to_buffer(&shadows.views, 0, &self.views, 0, shadows.views.size());
    }

    pub fn read(&self, gpu: &GpuContext) -> Result<ShadowInputs, String> {
        let atlas = unpad(
            &read_bytes(gpu, &self.atlas)?,
            self.side * DEPTH_TEXEL,
            self.side,
        );
        Ok(ShadowInputs {
            views: read_bytes(gpu, &self.views)?,
            side: self.side,
            atlas: bytemuck::pod_collect_to_vec(&atlas),
        })
    }
}

impl ShadowInputs {
    /// Binds `SHADOW_VIEWS`, `SHADOW_ATLAS` and the renderer's shadow sampler (bilinear,
    /// clamped, lit where the reference ≥ the texel: reversed Z) on a host dispatch.
    pub fn bind(&self, d: &mut Dispatch<'_>) -> Result<(), EvalError> {
        d.set_buffer("SHADOW_VIEWS", &self.views)?;
        d.set_texture(
            "SHADOW_ATLAS",
            HostTexture::depth(self.side, self.side, 1, &self.atlas),
        )?;
        d.set_sampler(
            "SHADOW_SAMPLER",
            HostSampler {
                linear: true,
                address: Address::ClampToEdge,
                compare: Some(Compare::GreaterEqual),
            },
        )
    }
}
