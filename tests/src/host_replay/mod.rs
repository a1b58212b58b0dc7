//! A compute kernel replayed on the host from exactly what the GPU bound.
//!
//! The renderer keeps, when asked (`ShaderProgram::record_bindings`), the resources of every bind
//! group a program built. [`BindingsProbe`], a pass inserted right after the kernel's pass, reads
//! that record inside the same frame and copies every buffer and texture the kernel was given
//! (a multisampled `u32` texture through `shaders_gen`'s `sample_copy`, since a multisampled
//! texture cannot be copied to a buffer). After the frame, [`BindingsProbe::take`] reads the
//! copies back as [`BoundInputs`], which bind them by name on a host [`Dispatch`] of the same
//! kernel compiled from its source: the host sees what the GPU saw, not a second gathering of
//! it.
//!
//! Samplers cannot be read back from wgpu: the caller states each one's settings, and binding
//! fails, naming the sampler, where a recorded sampler has none.

mod sample_copier;

use sample_copier::{SampleCopier, TextureShape};

use std::sync::Mutex;

use codegen::interp::{Dispatch, EvalError, HostSampler, HostTexture, Value};
use renderer::GpuContext;
use renderer::frame::RenderError;
use renderer::frame_data::{FrameInputs, FrameResources, VisibilitySamples};
use renderer::graph::{BufferAccess, ImportAccess, PassContext, RenderGraph, TextureAccess};
use renderer::passes::Pass;
use renderer::shader::ShaderProgram;
use shader_bind::BoundResource;

use crate::frame_probe::{copy_target, padded_row, read_bytes, unpad};

/// One bound resource's copy, waiting to be read back.
#[derive(Debug)]
enum Copy {
    Buffer {
        name: &'static str,
        copy: wgpu::Buffer,
    },
    Texture {
        name: &'static str,
        copy: wgpu::Buffer,
        shape: TextureShape,
    },
    Sampler(&'static str),
}

/// The pass that copies what `program` last bound. Insert it right after the kernel's pass, on
/// a renderer whose program records its bindings. It reads the frame's HDR image, visibility
/// buffer, shadow atlas and light lists (where the frame has them) as copy sources, so the
/// graph gives them the usage a copy needs and orders the probe after their writers.
#[derive(Debug)]
pub struct BindingsProbe {
    program: ShaderProgram,
    copies: std::sync::Arc<Mutex<Result<Vec<Copy>, String>>>,
}

impl BindingsProbe {
    /// A probe of `program`'s bindings; it starts the program's record.
    pub fn new(program: &ShaderProgram) -> Self {
        program.record_bindings();
        Self {
            program: program.clone(),
            copies: std::sync::Arc::new(Mutex::new(Err("no frame was probed".into()))),
        }
    }

    /// The last probed frame's copies, read back.
    pub fn take(&self, gpu: &GpuContext) -> Result<BoundInputs, String> {
        let copies = std::mem::replace(
            &mut *self
                .copies
                .lock()
                .map_err(|_| "the probe's lock is poisoned")?,
            Err("no frame was probed since the last take".into()),
        )?;
        let mut inputs = BoundInputs::default();
        for copy in copies {
            match copy {
                Copy::Buffer { name, copy } => inputs.buffers.push((name, read_bytes(gpu, &copy)?)),
                Copy::Texture { name, copy, shape } => {
                    let bytes = read_bytes(gpu, &copy)?;
                    inputs.textures.push((name, TexelData::new(shape, &bytes)?));
                }
                Copy::Sampler(name) => inputs.samplers.push(name),
            }
        }
        Ok(inputs)
    }
}

impl Pass for BindingsProbe {
    fn name(&self) -> &'static str {
        "bindings probe"
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let device = frame.gpu.device();
        // A buffer the probe writes, so the graph keeps the pass (the graph holds it).
        let anchor = copy_target(device, "bindings probe anchor", 4);
        let mut out =
            resources.import_buffer(graph, "bindings probe", &anchor, ImportAccess::ReadWrite);
        let msaa = frame.config.msaa;
        let copier = (msaa > 1)
            .then(|| SampleCopier::new(&frame.gpu, msaa))
            .transpose()?;
        let mut pass = graph.add_pass(self.name());
        pass.write_buffer(&mut out, BufferAccess::CopyDst);
        if let Some(hdr) = resources.hdr {
            pass.read_texture(hdr, TextureAccess::CopySrc);
        }
        if let Some(vis) = &resources.visibility {
            let access = if msaa > 1 {
                TextureAccess::Sampled
            } else {
                TextureAccess::CopySrc
            };
            match vis.samples {
                VisibilitySamples::Targets { ids } => {
                    pass.read_texture(ids, access);
                    // The shading kernel tells sky by the depth (`VIS_DEPTH`).
                    if let Some(depth) = resources.depth {
                        pass.read_texture(depth, access);
                    }
                }
                VisibilitySamples::Buffer { samples } => {
                    pass.read_buffer(samples, BufferAccess::CopySrc);
                }
            }
        }
        if let Some(shadows) = &resources.shadows {
            pass.read_texture(shadows.atlas, TextureAccess::CopySrc);
        }
        if let Some(lists) = &resources.light_lists {
            pass.read_buffer(lists.grid, BufferAccess::CopySrc)
                .read_buffer(lists.indices, BufferAccess::CopySrc);
        }
        let (program, copies) = (self.program.clone(), self.copies.clone());
        pass.execute(move |ctx| {
            let copied = program
                .bound()
                .into_iter()
                .map(|(_, name, resource)| copy_resource(ctx, copier.as_ref(), name, &resource))
                .collect::<Result<Vec<_>, _>>();
            if let Ok(mut slot) = copies.lock() {
                *slot = copied;
            }
        });
        Ok(())
    }
}

/// Records the copy of one bound resource.
fn copy_resource(
    ctx: &mut PassContext<'_>,
    copier: Option<&SampleCopier>,
    name: &'static str,
    resource: &BoundResource,
) -> Result<Copy, String> {
    match resource {
        BoundResource::Buffer {
            buffer,
            offset,
            size,
        } => {
            if !buffer.usage().contains(wgpu::BufferUsages::COPY_SRC) {
                return Err(format!("`{name}`'s buffer cannot be copied (no COPY_SRC)"));
            }
            let size = size.map_or(buffer.size() - offset, |s| s.get());
            let copy = copy_target(ctx.device, name, size);
            ctx.encoder
                .copy_buffer_to_buffer(buffer, *offset, &copy, 0, size);
            Ok(Copy::Buffer { name, copy })
        }
        BoundResource::Texture(texture) => {
            let shape = TextureShape {
                width: texture.width(),
                height: texture.height(),
                layers: texture.depth_or_array_layers(),
                samples: texture.sample_count(),
                format: texture.format(),
            };
            let copy = if shape.samples > 1 {
                let copier = copier.ok_or(format!("`{name}` is multisampled, the frame not"))?;
                copier.copy(ctx, name, texture, shape)?
            } else {
                copy_texture(ctx, name, texture, shape)?
            };
            Ok(Copy::Texture { name, copy, shape })
        }
        BoundResource::Sampler(_) => Ok(Copy::Sampler(name)),
    }
}

/// Level 0 of every layer of `texture`, rows padded to the copy alignment.
fn copy_texture(
    ctx: &mut PassContext<'_>,
    name: &str,
    texture: &wgpu::Texture,
    shape: TextureShape,
) -> Result<wgpu::Buffer, String> {
    if !texture.usage().contains(wgpu::TextureUsages::COPY_SRC) {
        return Err(format!("`{name}`'s texture cannot be copied (no COPY_SRC)"));
    }
    let texel = texel_bytes(shape.format).ok_or(format!("`{name}`: {:?}", shape.format))?;
    let row = padded_row(shape.width * texel);
    let copy = copy_target(
        ctx.device,
        name,
        u64::from(row) * u64::from(shape.height * shape.layers),
    );
    let aspect = if shape.format.is_depth_stencil_format() {
        wgpu::TextureAspect::DepthOnly
    } else {
        wgpu::TextureAspect::All
    };
    ctx.encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &copy,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(shape.height),
            },
        },
        wgpu::Extent3d {
            width: shape.width,
            height: shape.height,
            depth_or_array_layers: shape.layers,
        },
    );
    Ok(copy)
}

/// Bytes per texel of the formats a copy decodes.
fn texel_bytes(format: wgpu::TextureFormat) -> Option<u32> {
    use wgpu::TextureFormat as F;
    match format {
        F::R32Uint | F::R32Float | F::Depth32Float | F::Rgba8Unorm | F::Rgba8UnormSrgb => Some(4),
        F::Rgba16Float => Some(8),
        _ => None,
    }
}

/// A texture as read back: texels of every layer, then sample, tightly packed.
#[derive(Debug, Clone)]
pub struct TexelData {
    pub width: u32,
    pub height: u32,
    pub layers: u32,
    pub samples: u32,
    pub format: wgpu::TextureFormat,
    pub bytes: Vec<u8>,
}

impl TexelData {
    fn new(shape: TextureShape, copied: &[u8]) -> Result<Self, String> {
        let texel = texel_bytes(shape.format).ok_or(format!("{:?}", shape.format))?;
        let bytes = if shape.samples > 1 {
            copied.to_vec()
        } else {
            unpad(copied, shape.width * texel, shape.height * shape.layers)
        };
        Ok(Self {
            width: shape.width,
            height: shape.height,
            layers: shape.layers,
            samples: shape.samples,
            format: shape.format,
            bytes,
        })
    }

    /// The texels as the interpreter takes them: 4-vectors (`u32` for integer formats, `f32`
    /// otherwise, `srgb` decoding 8-bit colour to linear as an sRGB view does), one `f32` for
    /// depth.
    pub fn host(&self, srgb: bool) -> Result<HostTexture, String> {
        use wgpu::TextureFormat as F;
        let words = || self.bytes.chunks_exact(4);
        let f = |x: f32| Value::F32(x);
        let v4 = |c: [Value; 4]| Value::Vector(c.to_vec());
        let unorm = |b: u8, decode: bool| {
            let c = f32::from(b) / 255.0;
            if !decode {
                c
            } else if c <= 0.04045 {
                c / 12.92
            } else {
                ((c + 0.055) / 1.055).powf(2.4)
            }
        };
        let texels: Vec<Value> = match self.format {
            F::R32Uint => words()
                .map(|w| {
                    let u = u32::from_le_bytes([w[0], w[1], w[2], w[3]]);
                    v4([Value::U32(u), Value::U32(0), Value::U32(0), Value::U32(1)])
                })
                .collect(),
            F::R32Float => words()
                .map(|w| {
                    v4([
                        f(f32::from_le_bytes([w[0], w[1], w[2], w[3]])),
                        f(0.0),
                        f(0.0),
                        f(1.0),
                    ])
                })
                .collect(),
            F::Depth32Float => words()
                .map(|w| f(f32::from_le_bytes([w[0], w[1], w[2], w[3]])))
                .collect(),
            F::Rgba8Unorm | F::Rgba8UnormSrgb => {
                let decode = srgb || self.format == F::Rgba8UnormSrgb;
                words()
                    .map(|w| {
                        v4([
                            f(unorm(w[0], decode)),
                            f(unorm(w[1], decode)),
                            f(unorm(w[2], decode)),
                            f(unorm(w[3], false)),
                        ])
                    })
                    .collect()
            }
            F::Rgba16Float => self
                .bytes
                .chunks_exact(8)
                .map(|t| {
                    let h =
                        |i: usize| f(half::f16::from_le_bytes([t[2 * i], t[2 * i + 1]]).to_f32());
                    v4([h(0), h(1), h(2), h(3)])
                })
                .collect(),
            other => return Err(format!("texels of {other:?} are not decoded")),
        };
        Ok(HostTexture {
            width: self.width,
            height: self.height,
            layers: self.layers,
            samples: self.samples,
            texels,
        })
    }
}

/// A host colour texture's texels as RGBA `f32` (NaN where a texel is not a vector of `f32`):
/// what a kernel stored in a storage texture, to compare with the GPU's image.
pub fn rgba_texels(t: &HostTexture) -> Vec<[f32; 4]> {
    t.texels
        .iter()
        .map(|t| match t {
            Value::Vector(c) => {
                let f = |i: usize| match c.get(i) {
                    Some(Value::F32(x)) => *x,
                    _ => f32::NAN,
                };
                [f(0), f(1), f(2), f(3)]
            }
            _ => [f32::NAN; 4],
        })
        .collect()
}

/// What a kernel's bind groups held in one frame, read back.
#[derive(Debug, Clone, Default)]
pub struct BoundInputs {
    /// Buffer contents by binding name.
    pub buffers: Vec<(&'static str, Vec<u8>)>,
    /// Textures by binding name.
    pub textures: Vec<(&'static str, TexelData)>,
    /// The samplers bound (settings are not readable).
    pub samplers: Vec<&'static str>,
}

impl BoundInputs {
    /// The texture bound as `name`.
    pub fn texture(&self, name: &str) -> Option<&TexelData> {
        self.textures
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, t)| t)
    }

    /// Binds everything on `d`: buffers as they were; textures decoded (`srgb_views`: those
    /// bound through an sRGB view of a linear texture), but `outputs` (storage textures the
    /// kernel writes) all zero; each sampler with its setting in `samplers`.
    pub fn bind(
        &self,
        d: &mut Dispatch<'_>,
        srgb_views: &[&str],
        outputs: &[&str],
        samplers: &[(&str, HostSampler)],
    ) -> Result<(), EvalError> {
        for (name, bytes) in &self.buffers {
            d.set_buffer(name, bytes)?;
        }
        for (name, data) in &self.textures {
            let mut texture = data
                .host(srgb_views.contains(name))
                .map_err(|e| EvalError::Type(format!("`{name}`: {e}")))?;
            if outputs.contains(name) {
                let zero = Value::Vector(vec![Value::F32(0.0); 4]);
                texture.texels.iter_mut().for_each(|t| *t = zero.clone());
            }
            d.set_texture(name, texture)?;
        }
        for name in &self.samplers {
            let (_, sampler) = samplers.iter().find(|(n, _)| n == name).ok_or_else(|| {
                EvalError::Type(format!(
                    "the sampler `{name}` was bound; its settings were not given"
                ))
            })?;
            d.set_sampler(name, *sampler)?;
        }
        Ok(())
    }
}
