//! The overlay kept between frames and erased instead of cleared.
//!
//! On the deferred paths with MSAA, blended surfaces and particles are drawn into a transparent
//! multisampled overlay ([`FrameResources::hdr_overlay`]) that the overlay pass lays over the
//! shaded image. Clearing that target every frame was most of its cost: on the H200 a
//! multisampled clear moves about 56 GB/s, 1.17 ms for the 66 MB overlay at 1080p MSAA 4, where
//! the blended draws themselves take 0.70 ms (BENCHMARKS.md).
//!
//! So the overlay is a texture the forward pass keeps ([`KeptOverlay`]), loaded, never cleared,
//! and each pass that draws into it also registers an eraser
//! ([`FrameResources::add_overlay_eraser`]). The overlay pass runs the erasers after it has read
//! the overlay: each draws its pass's geometry again with the same vertex stage and
//! `overlay_erase`'s fragment stage, no depth test, no face culled and no blending
//! ([`EraseStage::pipeline`]), so every sample a layer touched (and any the depth test or a
//! discard spared) is transparent again for the next frame. A new texture starts zeroed (wgpu
//! initialises it on first use), so the overlay is transparent at the start of every frame.

use std::sync::{Mutex, PoisonError};

use shaders_gen::deferred::overlay_erase;

use crate::GpuContext;
use crate::frame_data::{FrameResources, HDR_FORMAT, RenderError, RendererConfig};
use crate::graph::{Handle, ImportAccess, RenderGraph, Texture, TextureDesc};
use crate::shader::ShaderProgram;

/// The multisampled overlay a forward pass keeps between frames, made again when the frame's
/// size or sample count changes.
#[derive(Debug, Default)]
pub(crate) struct KeptOverlay(Mutex<Option<wgpu::Texture>>);

impl KeptOverlay {
    /// This frame's overlay, imported into `graph` (created zeroed at the frame's size and
    /// sample count if the kept one differs).
    pub(crate) fn import(
        &self,
        device: &wgpu::Device,
        graph: &mut RenderGraph,
        resources: &mut FrameResources,
        c: &RendererConfig,
    ) -> Handle<Texture> {
        let desc = TextureDesc::new_2d(c.width, c.height, HDR_FORMAT).with_samples(c.msaa);
        let mut kept = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        let texture = match kept.as_ref() {
            Some(t) if desc.describes(t) => t.clone(),
            _ => {
                let usage =
                    wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
                kept.insert(desc.create(device, "hdr overlay", usage))
                    .clone()
            }
        };
        resources.import_texture(graph, "hdr overlay", &texture, ImportAccess::ReadWrite)
    }
}

/// `overlay_erase`'s program, whose fragment stage every erase pipeline takes.
#[derive(Debug, Clone)]
pub(crate) struct EraseStage {
    program: ShaderProgram,
}

impl EraseStage {
    pub(crate) fn new(gpu: &GpuContext) -> Result<Self, RenderError> {
        Ok(Self {
            program: gpu.program(overlay_erase::variant(overlay_erase::VariantKey {}))?,
        })
    }

    /// The erase pipeline of a pass that draws into the overlay with `program`'s vertex stage
    /// `vertex_entry` over `buffers`: that program's layout (so the pass's bind groups and draws
    /// serve unchanged), `fs_erase` writing transparent black into every covered sample, no
    /// depth test, no face culled, no blending.
    pub(crate) fn pipeline(
        &self,
        device: &wgpu::Device,
        (program, vertex_entry): (&ShaderProgram, &str),
        buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
        msaa: u32,
    ) -> wgpu::RenderPipeline {
        program.render_pipeline(
            device,
            &wgpu::RenderPipelineDescriptor {
                label: Some("overlay erase"),
                layout: Some(&program.pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &program.module,
                    entry_point: Some(vertex_entry),
                    compilation_options: Default::default(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState {
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: None,
                multisample: wgpu::MultisampleState {
                    count: msaa,
                    ..Default::default()
                },
                fragment: Some(wgpu::FragmentState {
                    module: &self.program.module,
                    entry_point: Some("fs_erase"),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: HDR_FORMAT,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            },
        )
    }
}
