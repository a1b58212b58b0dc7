//! Tonemapping: the resolved HDR colour through exposure and a filmic curve into the caller's
//! target (an sRGB format gets sRGB output).
//!
//! Two ways, the same image (within one 8-bit step: the compute kernel encodes sRGB itself):
//! - **a compute kernel** (`shaders_gen::forward::tonemap_compute`), where
//!   [`RendererConfig::compute_tonemap`] is set (the default) and the output format is
//!   `Rgba8Unorm` or `Rgba8UnormSrgb`: it writes a target stored as `Rgba8Unorm` with
//!   `STORAGE_BINDING` itself, encoding sRGB where the output format is sRGB
//!   ([`crate::frame::create_target`] gives such a target); otherwise it writes an internal
//!   `Rgba8Unorm` storage image, and a copy puts it into a target with `COPY_DST` (storage
//!   images cannot be sRGB, but the two formats copy into each other). On GPUs whose fragment
//!   rate is far below their compute rate the kernel costs a tenth of the fragment pass, and
//!   the copy five times the kernel (BENCHMARKS.md).
//! - **a full-screen fragment pass** (`shaders_gen::forward::tonemap`) everywhere else: a
//!   target that takes neither (a swap chain with `RENDER_ATTACHMENT` only), other
//!   output formats (`Bgra8UnormSrgb`, float targets).

use crate::frame_data::ConfigError;
use shaders_gen::forward::{tonemap, tonemap_compute};

use super::{Pass, draw_fullscreen, fullscreen_pipeline, groups_8x8};
use crate::GpuContext;
use crate::frame_data::{
    FrameInputs, FrameResources, FrameView, RenderError, RendererConfig, output_view,
};
use crate::graph::{Handle, RenderGraph, Texture, TextureAccess, TextureDesc};
use crate::shader::ShaderProgram;

/// The format of the compute kernel's image, and (up to sRGB) of the targets it serves.
const STORAGE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The tonemap pass: its programs, pipelines and parameters.
#[derive(Debug)]
pub struct TonemapPass {
    program: ShaderProgram,
    pipeline: wgpu::RenderPipeline,
    /// The compute kernel, where the configuration asks for it and the output format allows.
    compute: Option<(ShaderProgram, wgpu::ComputePipeline)>,
    params: wgpu::Buffer,
}

impl TonemapPass {
    pub fn new(gpu: &GpuContext, config: &RendererConfig) -> Result<Self, RenderError> {
        let key = tonemap::VariantKey {
            curve: tonemap::Curve::Curve0,
        };
        let program = gpu.program(tonemap::variant(key))?;
        let compute = if compute_serves(config) {
            let key = tonemap_compute::VariantKey {
                curve: tonemap_compute::Curve::Curve0,
                srgb: config.output_format.is_srgb(),
            };
            let program = gpu.program(tonemap_compute::variant(key))?;
            let pipeline = program.compute_pipeline(gpu.device(), "cs_tonemap")?;
            Some((program, pipeline))
        } else {
            None
        };
        Ok(Self {
            pipeline: fullscreen_pipeline(
                gpu.device(),
                &program,
                "fs_tonemap",
                config.output_format,
            ),
            program,
            compute,
            params: gpu.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some("tonemap"),
                size: size_of::<tonemap::TonemapParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        })
    }

    /// The compute kernel: into the target where it is a storage image, else into a new
    /// storage image copied into the target.
    fn add_compute(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
        (hdr, route): (Handle<Texture>, Route),
        (program, pipeline): (ShaderProgram, wgpu::ComputePipeline),
    ) {
        let c = &frame.config;
        let mut image = if route == Route::Direct {
            resources.output
        } else {
            let desc = TextureDesc::new_2d(c.width, c.height, STORAGE_FORMAT);
            graph.create_texture("tonemapped", desc)
        };
        let written = image;
        let groups = groups_8x8((c.width, c.height));
        let params = self.params.clone();
        graph
            .add_pass(self.name())
            .read_texture(hdr, TextureAccess::Sampled)
            .write_texture(&mut image, TextureAccess::StorageWrite)
            .execute(move |ctx| {
                let hdr_view = ctx.texture(hdr).create_view(&Default::default());
                let out_view = ctx.texture(written).create_view(&Default::default());
                let group = tonemap_compute::Group0 {
                    params: params.as_entire_buffer_binding(),
                    hdr: &hdr_view,
                    out: &out_view,
                }
                .bind_group(
                    ctx.device,
                    program.layout(0),
                    program.variant,
                    "tonemap",
                );
                let Some(group) = ctx.bind(group) else {
                    return;
                };
                let mut pass = ctx.encoder.begin_compute("tonemap");
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, &group, &[]);
                pass.dispatch_workgroups(groups.0, groups.1, 1);
            });
        if route == Route::Direct {
            resources.output = image;
            return;
        }
        let target = resources.output;
        graph
            .add_pass("tonemap copy")
            .read_texture(image, TextureAccess::CopySrc)
            .write_texture(&mut resources.output, TextureAccess::CopyDst)
            .execute(move |ctx| {
                let (source, destination) =
                    (ctx.texture(image).clone(), ctx.texture(target).clone());
                ctx.encoder.copy_texture_to_texture(
                    source.as_image_copy(),
                    destination.as_image_copy(),
                    source.size(),
                );
            });
    }
}

/// How a frame is tonemapped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Route {
    /// The kernel writes the target (an `Rgba8Unorm` storage image).
    Direct,
    /// The kernel writes an image of its own, copied into the target.
    Copied,
    /// The full-screen fragment pass.
    Fragment,
}

/// How a frame into a target stored as `stored` with `usage` is tonemapped where the compute
/// kernel exists (`compute_serves`).
fn route(stored: wgpu::TextureFormat, usage: wgpu::TextureUsages) -> Route {
    use wgpu::TextureUsages as U;
    if stored == STORAGE_FORMAT && usage.contains(U::STORAGE_BINDING) {
        Route::Direct
    } else if usage.contains(U::COPY_DST) {
        Route::Copied
    } else {
        Route::Fragment
    }
}

/// Whether `config` tonemaps in compute where the target allows it.
fn compute_serves(config: &RendererConfig) -> bool {
    config.compute_tonemap && config.output_format.remove_srgb_suffix() == STORAGE_FORMAT
}

impl Pass for TonemapPass {
    fn name(&self) -> &'static str {
        "tonemap"
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let c = &frame.config;
        // The particle-atlas view shows the lit atlas, fitted to the target's shorter side.
        let atlas = resources
            .particles
            .as_ref()
            .filter(|_| c.view == FrameView::ParticleAtlas)
            .and_then(|p| p.lit_atlas.map(|a| (a, p.atlas_side)));
        let (source, scale) = match atlas {
            Some((a, side)) => (Some(a), side as f32 / c.width.min(c.height) as f32),
            None => (resources.hdr, 1.0),
        };
        let hdr = source.ok_or(RenderError::Config(ConfigError::MissingInput {
            pass: "tonemap",
            input: if c.view == FrameView::ParticleAtlas {
                "particle lighting atlas (the frame has no particles)"
            } else {
                "HDR colour"
            },
        }))?;
        let params = tonemap::TonemapParams::new(c.exposure, scale);
        frame
            .gpu
            .queue()
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let route = route(frame.target_format, frame.target_usage);
        if let (Some(kernel), Route::Direct | Route::Copied) = (&self.compute, route) {
            self.add_compute(graph, frame, resources, (hdr, route), kernel.clone());
            return Ok(());
        }
        let (target, output_format) = (resources.output, c.output_format);
        let program = self.program.clone();
        let (pipeline, params) = (self.pipeline.clone(), self.params.clone());
        graph
            .add_pass(self.name())
            .read_texture(hdr, TextureAccess::Sampled)
            .write_texture(&mut resources.output, TextureAccess::ColorAttachment)
            .execute(move |ctx| {
                let hdr_view = ctx.texture(hdr).create_view(&Default::default());
                let out_view = output_view(ctx.texture(target), output_format);
                let group = tonemap::Group0 {
                    params: params.as_entire_buffer_binding(),
                    hdr: &hdr_view,
                }
                .bind_group(
                    ctx.device,
                    program.layout(0),
                    program.variant,
                    "tonemap",
                );
                draw_fullscreen(ctx, "tonemap", &pipeline, group, &out_view);
            });
        Ok(())
    }
}
