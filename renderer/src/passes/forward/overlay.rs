//! The overlay pass: on the deferred paths with MSAA, resolves what was drawn over the deferred
//! image (blended surfaces and particles, drawn into a transparent multisampled overlay,
//! `FrameResources::hdr_overlay`) and lays it over that image, in one compute dispatch into a
//! new HDR texture.
//!
//! This replaces expanding the deferred image into every sample of a multisampled target and
//! resolving it again, which wrote every sample of the screen to draw a few blended surfaces.
//! The overlay is drawn into, never resolved by a render pass; this pass reads its samples and
//! the image and writes one single-sample image. The result is the same up to half-float
//! rounding: see `shaders_gen::deferred::hdr_overlay`. The overlay is kept between frames and
//! never cleared: after reading it, this pass runs the erasers of the passes that drew into it
//! (`crate::passes::overlay_erase`).

use shaders_gen::deferred::hdr_overlay;

use crate::GpuContext;
use crate::frame_data::{ConfigError, FrameInputs, FrameResources, HDR_FORMAT, RenderError};
use crate::graph::{RenderGraph, TextureAccess, TextureDesc};
use crate::passes::{Pass, groups_8x8};
use crate::shader::ShaderProgram;

/// The overlay pass: its program and compute pipeline.
#[derive(Debug)]
pub struct OverlayPass {
    program: ShaderProgram,
    pipeline: wgpu::ComputePipeline,
}

impl OverlayPass {
    /// The pass for `msaa` samples (2, 4 or 8; without MSAA nothing is drawn into an overlay).
    pub fn new(gpu: &GpuContext, msaa: u32) -> Result<Self, RenderError> {
        let msaa = hdr_overlay::Msaa::from_value(msaa).ok_or_else(|| {
            RenderError::Config(ConfigError::SampleCount {
                asked: msaa,
                supported: hdr_overlay::Msaa::ALL.iter().map(|m| m.value()).collect(),
            })
        })?;
        let program = gpu.program(hdr_overlay::variant(hdr_overlay::VariantKey { msaa }))?;
        let pipeline = program.compute_pipeline(gpu.device(), "lay_over")?;
        Ok(Self { program, pipeline })
    }
}

impl Pass for OverlayPass {
    fn name(&self) -> &'static str {
        "overlay"
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        // Nothing was drawn over the deferred image (no blended surfaces, no particles).
        let Some(mut overlay) = resources.hdr_overlay.take() else {
            return Ok(());
        };
        let shaded = resources
            .hdr
            .ok_or(RenderError::Config(ConfigError::MissingInput {
                pass: "overlay",
                input: "deferred HDR image",
            }))?;
        let c = &frame.config;
        let mut hdr =
            graph.create_texture("hdr", TextureDesc::new_2d(c.width, c.height, HDR_FORMAT));
        let groups = groups_8x8((c.width, c.height));
        let (program, pipeline) = (self.program.clone(), self.pipeline.clone());
        graph
            .add_pass(self.name())
            .read_texture(shaded, TextureAccess::Sampled)
            .read_texture(overlay, TextureAccess::Sampled)
            .write_texture(&mut hdr, TextureAccess::StorageWrite)
            .execute(move |ctx| {
                let view = |h| ctx.texture(h).create_view(&Default::default());
                let (shaded_view, overlay_view, out_view) =
                    (view(shaded), view(overlay), view(hdr));
                let group = hdr_overlay::Group0 {
                    shaded: &shaded_view,
                    overlay: &overlay_view,
                    hdr_out: &out_view,
                }
                .bind_group(
                    ctx.device,
                    program.layout(0),
                    program.variant,
                    "hdr overlay",
                );
                let Some(group) = ctx.bind(group) else {
                    return;
                };
                let mut pass = ctx.encoder.begin_compute("overlay");
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, &group, &[]);
                pass.dispatch_workgroups(groups.0, groups.1, 1);
            });
        resources.hdr = Some(hdr);
        // The overlay is kept, not cleared: what was drawn into it is erased now that it is
        // read (`passes::overlay_erase`).
        for erase in resources.take_overlay_erasers() {
            erase(graph, &mut overlay);
        }
        Ok(())
    }
}
