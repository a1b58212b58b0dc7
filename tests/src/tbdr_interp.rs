//! `tbdr::shade` run by the DSL's host interpreter on the inputs of a real frame.
//!
//! [`KernelInputsProbe`], a pass inserted right after TBDR shading, copies what the kernel bound
//! that frame (its parameters, light spheres, punctual and directional light records with the
//! frame's shadow indices, the shadow views and the shadow atlas's depth) and what it wrote (the
//! HDR image). `TbdrPass`'s recording gives the G-buffer, every sample of it, and the edge bits.
//! [`host_shade`] hands the same inputs to the kernel compiled from `shaders_gen`'s source text
//! and returns the image and edge bits it computed, for the tests to compare with the GPU's.

use renderer::frame::ConfigError;
use std::sync::Mutex;

use codegen::Compiled;
use codegen::interp::{Dispatch, EvalError, HostTexture, Schedule, Value};
use glam::Vec4;
use renderer::frame::RenderError;
use renderer::frame_data::{FrameInputs, FrameResources};
use renderer::graph::{BufferAccess, ImportAccess, RenderGraph, TextureAccess};
use renderer::passes::Pass;
use renderer::passes::deferred::TbdrRecord;
use renderer::passes::deferred::tiled_shading::kernel_params;
use shaders_gen::deferred::tbdr::{CAPTURE_WORDS, TbdrParams};

use crate::frame_probe::{ShadowCopies, ShadowInputs, copy_target, padded_row, read_bytes, unpad};

/// Source text of the TBDR module and the libraries it uses.
pub const TBDR_SOURCE: &str = include_str!("../../shaders_gen/src/deferred/tiled_shading.rs");
const LIBRARY_SOURCES: [&str; 7] = [
    include_str!("../../shaders_gen/src/deferred/gbuffer_read.rs"),
    include_str!("../../shaders_gen/src/shared/lights.rs"),
    include_str!("../../shaders_gen/src/shared/brdf.rs"),
    include_str!("../../shaders_gen/src/shared/grid.rs"),
    include_str!("../../shaders_gen/src/shared/shadow.rs"),
    include_str!("../../shaders_gen/src/shared/normals.rs"),
    include_str!("../../shaders_gen/src/shared/samples.rs"),
];

/// Compiles the TBDR module from `source` (its text, or a mutation of it) with its libraries.
pub fn compile(source: &str) -> Result<Compiled, String> {
    let mut modules =
        codegen::compile_source_all_with(source, &LIBRARY_SOURCES).map_err(|e| e.to_string())?;
    if modules.is_empty() {
        return Err("no shader module in the source".into());
    }
    let (name, compiled) = modules.swap_remove(0);
    compiled.map_err(|e| format!("{name} does not compile: {e}"))
}

/// Bytes per `Rgba16Float` texel (the HDR image).
const HDR_TEXEL: u32 = 8;

/// The GPU copies one probed frame left, and what the probe knew on the CPU.
#[derive(Debug)]
struct Copies {
    params: TbdrParams,
    spheres: Vec<Vec4>,
    size: (u32, u32),
    lights: wgpu::Buffer,
    directional: wgpu::Buffer,
    shadows: ShadowCopies,
    hdr: wgpu::Buffer,
}

/// A pass that copies the TBDR kernel's inputs and output of every frame, for [`ProbedFrame`].
/// Insert it after `"tbdr shading"`, on a renderer whose `TbdrPass` records.
#[derive(Debug, Default)]
pub struct KernelInputsProbe {
    copies: Mutex<Option<Copies>>,
}

/// Everything `tbdr::shade` read and wrote in one frame.
#[derive(Debug, Clone)]
pub struct ProbedFrame {
    pub params: TbdrParams,
    /// Bounding sphere (centre, radius) per punctual light.
    pub spheres: Vec<Vec4>,
    /// `LIGHTS` and `DIRECTIONAL` as the GPU held them (with this frame's shadow indices).
    pub lights: Vec<u8>,
    pub directional: Vec<u8>,
    pub shadows: ShadowInputs,
    /// The kernel's HDR output, row-major RGBA.
    pub hdr: Vec<[f32; 4]>,
    /// The G-buffer and edge bits of the same frame.
    pub record: TbdrRecord,
}

impl KernelInputsProbe {
    /// What the last frame copied, with `record` (that frame's `TbdrPass::recorded`).
    pub fn take(
        &self,
        gpu: &renderer::GpuContext,
        record: TbdrRecord,
    ) -> Result<ProbedFrame, String> {
        let copies = self
            .copies
            .lock()
            .map_err(|_| "the probe's lock is poisoned")?
            .take()
            .ok_or("no frame was probed")?;
        let (w, h) = copies.size;
        let hdr = unpad(&read_bytes(gpu, &copies.hdr)?, w * HDR_TEXEL, h)
            .chunks_exact(HDR_TEXEL as usize)
            .map(|t| {
                let half = |i: usize| half::f16::from_le_bytes([t[2 * i], t[2 * i + 1]]).to_f32();
                [half(0), half(1), half(2), half(3)]
            })
            .collect::<Vec<_>>();
        if hdr.len() != (w * h) as usize {
            return Err(format!(
                "{} HDR texels read back, {w}×{h} expected",
                hdr.len()
            ));
        }
        Ok(ProbedFrame {
            params: copies.params,
            spheres: copies.spheres,
            lights: read_bytes(gpu, &copies.lights)?,
            directional: read_bytes(gpu, &copies.directional)?,
            shadows: copies.shadows.read(gpu)?,
            hdr,
            record,
        })
    }
}

impl Pass for KernelInputsProbe {
    fn name(&self) -> &'static str {
        "tbdr inputs probe"
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let missing = |input| {
            RenderError::Config(ConfigError::MissingInput {
                pass: "tbdr inputs probe",
                input,
            })
        };
        let hdr = resources.hdr.ok_or(missing("HDR colour"))?;
        let shadows = resources.shadows.clone().ok_or(missing("shadow atlas"))?;
        let device = frame.gpu.device();
        let buffer = |label, size: u64| copy_target(device, label, size);
        let (w, h) = (frame.config.width, frame.config.height);
        let lights = &frame.lights;
        let copies = Copies {
            params: kernel_params(frame, lights.punctual.len() as u32, true),
            spheres: lights
                .spheres
                .iter()
                .map(|s| s.center.extend(s.radius))
                .collect(),
            size: (w, h),
            lights: buffer("probe lights", lights.punctual_buffer.size()),
            directional: buffer("probe directional", lights.directional_buffer.size()),
            shadows: ShadowCopies::new(device, &shadows, frame.config.fitted_shadows().atlas_size),
            hdr: buffer(
                "probe hdr",
                u64::from(padded_row(w * HDR_TEXEL)) * u64::from(h),
            ),
        };
        // The HDR copy is the pass's tracked output, so the graph keeps the pass.
        let mut out =
            resources.import_buffer(graph, "probe hdr", &copies.hdr, ImportAccess::ReadWrite);
        let target = out;
        let sources = [
            (lights.punctual_buffer.clone(), copies.lights.clone()),
            (
                lights.directional_buffer.clone(),
                copies.directional.clone(),
            ),
        ];
        let shadow_copies = copies.shadows.clone();
        graph
            .add_pass(self.name())
            .read_texture(hdr, TextureAccess::CopySrc)
            .read_texture(shadows.atlas, TextureAccess::CopySrc)
            .write_buffer(&mut out, BufferAccess::CopyDst)
            .execute(move |ctx| {
                let image = ctx.texture(hdr).clone();
                let hdr_copy = ctx.buffer(target).clone();
                ctx.encoder.copy_texture_to_buffer(
                    image.as_image_copy(),
                    wgpu::TexelCopyBufferInfo {
                        buffer: &hdr_copy,
                        layout: wgpu::TexelCopyBufferLayout {
                            offset: 0,
                            bytes_per_row: Some(padded_row(w * HDR_TEXEL)),
                            rows_per_image: Some(h),
                        },
                    },
                    image.size(),
                );
                shadow_copies.record(ctx, &shadows);
                for (from, to) in &sources {
                    ctx.encoder
                        .copy_buffer_to_buffer(from, 0, to, 0, from.size());
                }
            });
        if let Ok(mut slot) = self.copies.lock() {
            *slot = Some(copies);
        }
        Ok(())
    }
}

/// What the host's `tbdr::shade` wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct HostShade {
    /// Row-major RGBA.
    pub hdr: Vec<[f32; 4]>,
    pub edge_bits: Vec<u32>,
}

/// How a host run is set up.
#[derive(Debug, Clone, Copy)]
pub struct HostRun {
    pub subgroup_size: u32,
    pub schedule: Schedule,
    pub race_detection: bool,
    /// Reads of workgroup memory nothing wrote are errors.
    pub unwritten_reads: bool,
}

/// Entry point `entry` of `c`'s variant `axes` on the host, bound to `frame`'s inputs (`HDR_OUT`
/// and `EDGE_BITS` zero, `CAPTURE` room for every sample).
fn bound<'c>(
    c: &'c Compiled,
    axes: &[(&str, i64)],
    frame: &ProbedFrame,
    run: HostRun,
    entry: &str,
) -> Result<Dispatch<'c>, EvalError> {
    let env = crate::cull_interp::variant(c, axes);
    let r = &frame.record;
    let (w, h, msaa) = (r.width, r.height, r.msaa);
    let mut d = Dispatch::new(&c.module, env, entry)?
        .with_subgroup_size(run.subgroup_size)?
        .with_schedule(run.schedule)
        .with_race_detection(run.race_detection)
        .with_unwritten_read_check(run.unwritten_reads);
    d.set_buffer("PARAMS", bytemuck::bytes_of(&frame.params))?;
    d.set_buffer("LIGHTS", &frame.lights)?;
    d.set_buffer("DIRECTIONAL", &frame.directional)?;
    let spheres: &[u8] = if frame.spheres.is_empty() {
        &[0; 16]
    } else {
        bytemuck::cast_slice(&frame.spheres)
    };
    d.set_buffer("SPHERES", spheres)?;
    frame.shadows.bind(&mut d)?;
    d.set_buffer("EDGE_BITS", &vec![0; (w * h).div_ceil(32) as usize * 4])?;
    d.set_buffer("CAPTURE", &vec![0; r.gbuffer.len() * 4])?;
    let words = CAPTURE_WORDS as usize;
    let samples = || r.gbuffer.chunks_exact(words);
    let vector = |v: &[f32]| Value::Vector(v.iter().map(|c| Value::F32(*c)).collect());
    let colour = |from: usize| HostTexture {
        width: w,
        height: h,
        layers: 1,
        samples: msaa,
        texels: samples().map(|s| vector(&s[from..from + 4])).collect(),
    };
    let depth: Vec<f32> = samples().map(|s| s[0]).collect();
    let suffix = if msaa == 1 { "" } else { "_MS" };
    d.set_texture(
        &format!("DEPTH{suffix}"),
        HostTexture::depth(w, h, msaa, &depth),
    )?;
    d.set_texture(&format!("ALBEDO{suffix}"), colour(1))?;
    d.set_texture(&format!("NORMALS{suffix}"), colour(5))?;
    d.set_texture(&format!("RADIANCE{suffix}"), colour(9))?;
    // One channel (`R32Float`): loads as `(v, 0, 0, 1)`.
    let view_depth = HostTexture {
        width: w,
        height: h,
        layers: 1,
        samples: msaa,
        texels: samples().map(|s| vector(&[s[13], 0.0, 0.0, 1.0])).collect(),
    };
    d.set_texture(&format!("VIEW_DEPTH{suffix}"), view_depth)?;
    d.set_texture(
        "HDR_OUT",
        HostTexture {
            width: w,
            height: h,
            layers: 1,
            samples: 1,
            texels: vec![vector(&[0.0; 4]); (w * h) as usize],
        },
    )?;
    Ok(d)
}

/// `tbdr::capture_gbuffer` of `c`'s variant `axes` run on the host over `frame`'s G-buffer: the
/// capture it wrote.
pub fn host_capture(
    c: &Compiled,
    axes: &[(&str, i64)],
    frame: &ProbedFrame,
    run: HostRun,
) -> Result<Vec<f32>, EvalError> {
    let mut d = bound(c, axes, frame, run, "capture_gbuffer")?;
    let r = &frame.record;
    d.run([r.width.div_ceil(8), r.height.div_ceil(8), 1])?;
    Ok(bytemuck::pod_collect_to_vec(&d.buffer("CAPTURE")?))
}

/// `tbdr::shade` of `c`'s variant `axes` run on the host over `frame`'s inputs.
pub fn host_shade(
    c: &Compiled,
    axes: &[(&str, i64)],
    frame: &ProbedFrame,
    run: HostRun,
) -> Result<HostShade, EvalError> {
    let tile = axes
        .iter()
        .find(|(name, _)| *name == "tile")
        .map_or(8, |(_, t)| *t as u32);
    let mut d = bound(c, axes, frame, run, "shade")?;
    let r = &frame.record;
    d.run([r.width.div_ceil(tile), r.height.div_ceil(tile), 1])?;
    let hdr = crate::host_replay::rgba_texels(&d.texture("HDR_OUT")?);
    let edge_bits = bytemuck::pod_collect_to_vec(&d.buffer("EDGE_BITS")?);
    Ok(HostShade { hdr, edge_bits })
}
