//! Forward shading: PBR over the frame's light list (every light, or the culled cell lists)
//! into the MSAA HDR target, resolved to a single-sample HDR texture. Opaque draws first, then
//! blended draws back to front. After the pre-pass it tests depth with `LessEqual` against the
//! pre-Z depth (both vertex stages compute the position with the same `#[invariant]` code);
//! without one (the naive path) it writes its own.
//!
//! On the deferred paths opaque surfaces are shaded already; the pass then draws only blended
//! surfaces: without MSAA over the deferred image in place, with MSAA into a transparent
//! multisampled overlay (particles draw into it too) that [`OverlayPass`] resolves and lays over
//! the image.
//! It adds nothing when there are neither blended surfaces nor particles. On the compute
//! rasteriser's frame the blended surfaces test the rasteriser's samples themselves, their
//! fragments lit in compute first (`over_samples`), and the pass has no depth target.

pub(crate) mod bindings;
pub(crate) mod over_samples;
pub(crate) mod overlay;
pub(crate) mod programs;
mod record;

pub(crate) use bindings::{FrameGroup, lighting_buffer};
pub(crate) use overlay::OverlayPass;
pub(crate) use programs::MaterialPipelines;

use crate::frame_data::ConfigError;
use std::sync::Arc;

use shaders_gen::forward::forward;

use super::overlay_erase::{EraseStage, KeptOverlay};
use super::{MeshPipeline, Pass, depth_state, mesh_pipeline};
use crate::GpuContext;
use crate::frame_data::{
    BlendedDraws, DEPTH_FORMAT, FrameInputs, FrameResources, HDR_FORMAT, RenderError, RenderPath,
    RendererConfig,
};
use crate::graph::{BufferAccess, Handle, RenderGraph, Texture, TextureAccess, TextureDesc};
use crate::materials::MaterialProgram;
use crate::shader::ShaderProgram;
use over_samples::OverSamples;

/// The forward pass: its programs (glTF PBR's and every registered material program's) and
/// pipelines, and its lighting uniform.
#[derive(Debug)]
pub struct ForwardPass {
    pipelines: Arc<ForwardPipelines>,
    lighting: wgpu::Buffer,
    /// The overlay the blended surfaces are drawn into on the deferred paths with MSAA.
    overlay: KeptOverlay,
    /// On the compute rasteriser's frame, what the blended variant over its samples binds.
    over_samples: Option<OverSamples>,
}

/// The opaque and masked draws' programs and pipelines (`[double_sided][mirrored]` per
/// material program), and the one pipeline of every blended draw (glTF PBR's, no face culled:
/// the `blend` variant drops single-sided back faces itself, so the back-to-front order never
/// switches pipeline).
#[derive(Debug)]
struct ForwardPipelines {
    opaque: MaterialPipelines,
    blended: wgpu::RenderPipeline,
    /// The blended draws' program (`fs_forward_vis64`'s variant on the compute rasteriser's
    /// frame, whose group 0 is not the opaque programs').
    blended_program: ShaderProgram,
    /// Where the pass draws into an overlay: glTF PBR's blended program and the pipeline that
    /// erases what its draws covered (`passes::overlay_erase`).
    erase: Option<(ShaderProgram, wgpu::RenderPipeline)>,
    /// Over the compute rasteriser's samples (`vs_blend`, the records lit in compute): the
    /// blended pipeline that outputs the records (`fs_blend_listed`; `blended` is then the one
    /// that may shade, `fs_forward_vis64`).
    listed: Option<wgpu::RenderPipeline>,
}

impl ForwardPass {
    /// The pass of `config`, with pipelines for glTF PBR and every program of `materials`.
    pub fn new(
        gpu: &GpuContext,
        config: &RendererConfig,
        materials: &[MaterialProgram],
    ) -> Result<Self, RenderError> {
        let list = match config.path {
            RenderPath::Naive | RenderPath::NaivePrez => 0,
            RenderPath::Tiled
            | RenderPath::Depth25
            | RenderPath::Tbdr
            | RenderPath::TbdrPerSample
            | RenderPath::Deferred => 1,
            RenderPath::Clustered | RenderPath::Visibility => 2,
        };
        let scalarize = config.scalarize && config.path.is_culled();
        let prepass = config.path.has_prepass();
        let over_samples = config.reads_compute_samples();
        let make = |program: &ShaderProgram, faces: (bool, bool, bool)| {
            let depth = (!(over_samples && faces.0)).then_some(prepass);
            pipeline(gpu.device(), program, config.msaa, depth, faces)
        };
        let opaque =
            MaterialPipelines::new(gpu, materials, (list, false, scalarize), |p, d, m| {
                make(p, (false, d, m))
            })?;
        let blended = gpu.program(forward::variant(forward::VariantKey {
            list: forward::List::from_value(list).unwrap_or(forward::List::List0),
            blend: true,
            scalarize,
            // The forward programs are `msaa` 0; over the compute rasteriser's samples, the
            // blended variant has the frame's sample count.
            msaa: if over_samples {
                forward::Msaa::from_value(config.msaa)
                    .ok_or_else(|| ConfigError::shader_sample_count(config.msaa))?
            } else {
                forward::Msaa::Msaa0
            },
            vis64: over_samples,
        })?)?;
        let erase = if config.path.is_deferred() && config.msaa > 1 {
            let streams = super::vertex_streams(&super::FORWARD_STREAMS);
            let pipeline = EraseStage::new(gpu)?.pipeline(
                gpu.device(),
                (&blended, "vs_forward"),
                &super::stream_layouts(&streams),
                config.msaa,
            );
            Some((blended.clone(), pipeline))
        } else {
            None
        };
        let over_samples = match over_samples {
            true => Some(OverSamples::new(gpu.device(), &blended, config.msaa)?),
            false => None,
        };
        Ok(Self {
            pipelines: Arc::new(ForwardPipelines {
                blended: make(&blended, (true, true, false)),
                listed: over_samples.is_some().then(|| {
                    over_samples_pipeline(gpu.device(), &blended, config.msaa, "fs_blend_listed")
                }),
                blended_program: blended,
                opaque,
                erase,
            }),
            lighting: lighting_buffer(gpu.device()),
            overlay: KeptOverlay::default(),
            over_samples,
        })
    }
}

/// A forward pipeline of `program`; `prepass`: whether a pre-pass wrote the depth it tests,
/// `None` where the pass has no depth target (blended surfaces over the compute rasteriser's
/// samples: `vs_blend`, which pulls its vertices, and `fs_forward_vis64`, which tests the
/// samples itself).
fn pipeline(
    device: &wgpu::Device,
    program: &ShaderProgram,
    msaa: u32,
    prepass: Option<bool>,
    (blend, double_sided, mirrored): (bool, bool, bool),
) -> wgpu::RenderPipeline {
    if prepass.is_none() && blend {
        return over_samples_pipeline(device, program, msaa, "fs_forward_vis64");
    }
    mesh_pipeline(
        device,
        program,
        &MeshPipeline {
            label: if blend { "forward blend" } else { "forward" },
            vertex_entry: "vs_forward",
            streams: &super::FORWARD_STREAMS,
            double_sided,
            mirrored,
            // With a pre-pass, opaque surfaces are in the depth buffer already and blended ones
            // test against it; without one, opaque draws write depth themselves. Both keep the
            // last drawn of coincident surfaces (`LessEqual`), so naive equals the pre-pass paths
            // where surfaces coincide (the pre-pass keeps the nearest depth, and every draw at
            // that depth passes `LessEqual` after it, the last one's colour staying).
            depth: prepass
                .map(|prepass| depth_state(!(prepass || blend), wgpu::CompareFunction::LessEqual)),
            msaa,
            fragment: Some(("fs_forward", &[Some(color_target(blend))])),
        },
    )
}

/// The colour target of the forward pipelines: alpha accumulates as `One, OneMinusSrcAlpha`
/// where `blend`, so drawn into a transparent overlay the blended layers compose into one that
/// `OverlayPass` lays over the deferred image.
fn color_target(blend: bool) -> wgpu::ColorTargetState {
    wgpu::ColorTargetState {
        format: HDR_FORMAT,
        blend: blend.then_some(wgpu::BlendState::ALPHA_BLENDING),
        write_mask: wgpu::ColorWrites::ALL,
    }
}

/// A pipeline of the blended draws over the compute rasteriser's samples: `vs_blend` (its
/// vertices pulled, no vertex buffer) and `fragment` (`fs_blend_listed` or
/// `fs_forward_vis64`), no depth target (the fragment stage tests the samples), no face culled.
fn over_samples_pipeline(
    device: &wgpu::Device,
    program: &ShaderProgram,
    msaa: u32,
    fragment: &str,
) -> wgpu::RenderPipeline {
    mesh_pipeline(
        device,
        program,
        &MeshPipeline {
            label: "forward blend",
            vertex_entry: "vs_blend",
            streams: &[],
            double_sided: true,
            mirrored: false,
            depth: None,
            msaa,
            fragment: Some((fragment, &[Some(color_target(true))])),
        },
    )
}

/// The colour and depth targets of the pass.
struct Targets {
    /// The colour attachment.
    color: Handle<Texture>,
    /// Where `color` resolves to (the scene with MSAA).
    resolve: Option<Handle<Texture>>,
    depth: Depth,
    layer: Layer,
}

/// What the pass draws, and over what.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Layer {
    /// The whole scene, over the sky.
    Scene,
    /// The blended surfaces, over the deferred image, which is `color` (no MSAA).
    OverInPlace,
    /// The blended surfaces, into a transparent multisampled overlay (`color`, not resolved)
    /// that [`OverlayPass`] resolves and lays over the deferred image (MSAA).
    Overlay,
}

impl Pass for ForwardPass {
    fn name(&self) -> &'static str {
        "forward"
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let c = &frame.config;
        let missing = |input| {
            RenderError::Config(ConfigError::MissingInput {
                pass: "forward",
                input,
            })
        };
        let deferred = c.path.is_deferred();
        let has_blend = frame.scene.has_blended();
        if deferred && !has_blend && frame.particles.is_none() {
            return Ok(());
        }
        let lists = resources.light_lists.clone();
        if c.path.is_culled() && lists.is_none() && (!deferred || has_blend) {
            return Err(missing("light lists"));
        }
        let shaded = if deferred {
            Some(resources.hdr.ok_or(missing("deferred HDR image"))?)
        } else {
            None
        };
        let kept = |graph: &mut RenderGraph| {
            (self.overlay).import(frame.gpu.device(), graph, resources, c)
        };
        let (layer, mut color, mut resolve) = color_targets(graph, c, shaded, kept);
        let shadows = resources.shadows.clone().ok_or(missing("shadow atlas"))?;
        let group = FrameGroup::new(frame, &self.lighting, lists, shadows);
        let list = resources
            .scene_draws
            .clone()
            .ok_or(missing("the scene's draw batches"))?;
        // Over the compute rasteriser's samples the blended draws test them, not a depth
        // target, and are lit in compute first.
        let samples = match &self.over_samples {
            Some(o) if has_blend => Some(o.frame(graph, (frame, resources), (&group, &list))?),
            _ => None,
        };
        let mut depth = Depth::of(graph, c, resources.depth, self.over_samples.is_some());
        let mut pass = graph.add_pass(self.name());
        depth.declare(&mut pass);
        let targets = Targets {
            color,
            resolve,
            depth,
            layer,
        };
        if let Some(samples) = &samples {
            samples.read_by(&mut pass);
        }
        pass.write_texture(&mut color, TextureAccess::ColorAttachment);
        if let Some(h) = resolve.as_mut() {
            pass.write_texture(h, TextureAccess::ColorAttachment);
        }
        group.read_by(&mut pass);
        pass.read_buffer(list.args, BufferAccess::Indirect);
        if let BlendedDraws::Sorted { args, .. } = &list.blended {
            pass.read_buffer(*args, BufferAccess::Indirect);
        }
        let eraser = (layer == Layer::Overlay && has_blend)
            .then(|| self.blended_eraser(frame, (group.clone(), samples.clone()), list.clone()))
            .flatten();
        let record = self.recorder(frame, targets, (group, samples), list);
        pass.execute(record);
        if let Some(eraser) = eraser {
            resources.add_overlay_eraser(eraser);
        }
        if layer == Layer::Overlay {
            resources.hdr_overlay = Some(color);
            resources.hdr_multisampled = None;
        } else {
            resources.hdr = Some(resolve.unwrap_or(color));
            resources.hdr_multisampled = resolve.map(|_| color);
        }
        if let Depth::Own(own) = depth {
            resources.depth = Some(own);
        }
        Ok(())
    }
}

/// The forward pass's depth target.
#[derive(Clone, Copy)]
enum Depth {
    /// The pre-pass's, attached read-only: no pipeline of the pass writes depth.
    Prepass(Handle<Texture>),
    /// The pass's own, cleared and written (no pre-pass).
    Own(Handle<Texture>),
    /// None: blended surfaces over the compute rasteriser's samples test those.
    None,
}

impl Depth {
    /// The depth of a frame of `c` whose pre-pass left `prepass`, or none `over_samples`.
    fn of(
        graph: &mut RenderGraph,
        c: &RendererConfig,
        prepass: Option<Handle<Texture>>,
        over_samples: bool,
    ) -> Self {
        match prepass {
            _ if over_samples => Self::None,
            Some(d) => Self::Prepass(d),
            None => {
                let desc =
                    TextureDesc::new_2d(c.width, c.height, DEPTH_FORMAT).with_samples(c.msaa);
                Self::Own(graph.create_texture("depth", desc))
            }
        }
    }

    /// Declares `pass`'s use of the target.
    fn declare(&mut self, pass: &mut crate::graph::PassBuilder<'_>) {
        match self {
            Self::Prepass(d) => {
                pass.read_texture(*d, TextureAccess::DepthRead);
            }
            Self::Own(d) => {
                pass.write_texture(d, TextureAccess::DepthWrite);
            }
            Self::None => {}
        }
    }
}

/// What the pass draws (`Layer`), its colour attachment and where that resolves to: without
/// MSAA the deferred image `shaded` is drawn over in place; with MSAA, the kept overlay
/// `overlay` imports.
fn color_targets(
    graph: &mut RenderGraph,
    c: &RendererConfig,
    shaded: Option<Handle<Texture>>,
    overlay: impl FnOnce(&mut RenderGraph) -> Handle<Texture>,
) -> (Layer, Handle<Texture>, Option<Handle<Texture>>) {
    let desc = TextureDesc::new_2d(c.width, c.height, HDR_FORMAT);
    let multisampled = desc.with_samples(c.msaa);
    match shaded {
        Some(h) if c.msaa == 1 => (Layer::OverInPlace, h, None),
        Some(_) => (Layer::Overlay, overlay(graph), None),
        None if c.msaa > 1 => (
            Layer::Scene,
            graph.create_texture("hdr msaa", multisampled),
            Some(graph.create_texture("hdr", desc)),
        ),
        None => (Layer::Scene, graph.create_texture("hdr", desc), None),
    }
}
