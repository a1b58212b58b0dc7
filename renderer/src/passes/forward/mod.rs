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
//! It adds nothing when there are neither blended surfaces nor particles.

pub(crate) mod bindings;
pub(crate) mod overlay;
pub(crate) mod programs;

pub(crate) use bindings::{FrameGroup, lighting_buffer};
pub(crate) use overlay::OverlayPass;
pub(crate) use programs::MaterialPipelines;

use crate::frame_data::ConfigError;
use std::sync::Arc;

use shaders_gen::forward::forward;

use super::overlay_erase::{EraseStage, KeptOverlay};
use super::{MeshPipeline, Pass, SceneDraws, color_pass, depth_state, mesh_pipeline};
use crate::GpuContext;
use crate::frame_data::{
    BlendedDraws, DEPTH_FORMAT, FrameInputs, FrameResources, HDR_FORMAT, InstanceTable,
    OverlayEraser, PreparedScene, RenderError, RenderPath, RendererConfig, SceneDrawList,
};
use crate::graph::{BufferAccess, Handle, RenderGraph, Texture, TextureAccess, TextureDesc};
use crate::materials::MaterialProgram;
use crate::scene::VertexStreams;
use crate::shader::ShaderProgram;
use programs::BoundPrograms;

/// The forward pass: its programs (glTF PBR's and every registered material program's) and
/// pipelines, and its lighting uniform.
#[derive(Debug)]
pub struct ForwardPass {
    pipelines: Arc<ForwardPipelines>,
    lighting: wgpu::Buffer,
    /// The overlay the blended surfaces are drawn into on the deferred paths with MSAA.
    overlay: KeptOverlay,
}

/// The opaque and masked draws' programs and pipelines (`[double_sided][mirrored]` per
/// material program), and the one pipeline of every blended draw (glTF PBR's, no face culled:
/// the `blend` variant drops single-sided back faces itself, so the back-to-front order never
/// switches pipeline).
#[derive(Debug)]
struct ForwardPipelines {
    opaque: MaterialPipelines,
    blended: wgpu::RenderPipeline,
    /// Where the pass draws into an overlay: glTF PBR's blended program and the pipeline that
    /// erases what its draws covered (`passes::overlay_erase`).
    erase: Option<(ShaderProgram, wgpu::RenderPipeline)>,
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
        let make = |program: &ShaderProgram, faces| {
            pipeline(gpu.device(), program, config.msaa, prepass, faces)
        };
        let opaque =
            MaterialPipelines::new(gpu, materials, (list, false, scalarize), |p, d, m| {
                make(p, (false, d, m))
            })?;
        let blended = gpu.program(forward::variant(forward::VariantKey {
            list: forward::List::from_value(list).unwrap_or(forward::List::List0),
            blend: true,
            scalarize,
            // The forward programs (the visibility kernels are `msaa` above 0).
            msaa: forward::Msaa::Msaa0,
            vis64: false,
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
        Ok(Self {
            pipelines: Arc::new(ForwardPipelines {
                blended: make(&blended, (true, true, false)),
                opaque,
                erase,
            }),
            lighting: lighting_buffer(gpu.device()),
            overlay: KeptOverlay::default(),
        })
    }
}

fn pipeline(
    device: &wgpu::Device,
    program: &ShaderProgram,
    msaa: u32,
    prepass: bool,
    (blend, double_sided, mirrored): (bool, bool, bool),
) -> wgpu::RenderPipeline {
    let target = wgpu::ColorTargetState {
        format: HDR_FORMAT,
        // Alpha accumulates as `One, OneMinusSrcAlpha`, so drawn into a transparent overlay
        // the blended layers compose into one that `OverlayPass` lays over the deferred image.
        blend: blend.then_some(wgpu::BlendState::ALPHA_BLENDING),
        write_mask: wgpu::ColorWrites::ALL,
    };
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
            depth: if prepass || blend {
                depth_state(false, wgpu::CompareFunction::LessEqual)
            } else {
                depth_state(true, wgpu::CompareFunction::LessEqual)
            },
            msaa,
            fragment: Some(("fs_forward", &[Some(target)])),
        },
    )
}

/// The colour and depth targets of the pass.
struct Targets {
    /// The colour attachment.
    color: Handle<Texture>,
    /// Where `color` resolves to (the scene with MSAA).
    resolve: Option<Handle<Texture>>,
    depth: Handle<Texture>,
    /// Whether `depth` holds the pre-pass's depth (attached read-only) or is the pass's own
    /// (cleared and written).
    prepass: bool,
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
        let mut own_depth = resources.depth.is_none().then(|| {
            let desc = TextureDesc::new_2d(c.width, c.height, DEPTH_FORMAT).with_samples(c.msaa);
            graph.create_texture("depth", desc)
        });
        let targets = Targets {
            color,
            resolve,
            depth: resources
                .depth
                .or(own_depth)
                .ok_or(missing("depth buffer"))?,
            prepass: resources.depth.is_some(),
            layer,
        };
        let mut pass = graph.add_pass(self.name());
        match (resources.depth, own_depth.as_mut()) {
            (Some(d), _) => pass.read_texture(d, TextureAccess::DepthRead),
            (None, Some(d)) => pass.write_texture(d, TextureAccess::DepthWrite),
            (None, None) => &mut pass,
        };
        pass.write_texture(&mut color, TextureAccess::ColorAttachment);
        if let Some(h) = resolve.as_mut() {
            pass.write_texture(h, TextureAccess::ColorAttachment);
        }
        let shadows = resources.shadows.clone().ok_or(missing("shadow atlas"))?;
        let group = FrameGroup::new(frame, &self.lighting, lists, shadows);
        group.read_by(&mut pass);
        let list = resources
            .scene_draws
            .clone()
            .ok_or(missing("the scene's draw batches"))?;
        pass.read_buffer(list.args, BufferAccess::Indirect);
        if let BlendedDraws::Sorted { args, .. } = &list.blended {
            pass.read_buffer(*args, BufferAccess::Indirect);
        }
        let eraser = (layer == Layer::Overlay && has_blend)
            .then(|| self.blended_eraser(frame, group.clone(), list.clone()))
            .flatten();
        let record = self.recorder(frame, targets, group, list);
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
        if resources.depth.is_none() {
            resources.depth = own_depth;
        }
        Ok(())
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

impl ForwardPass {
    /// The eraser of the blended draws this frame draws into the overlay: the same draws with
    /// the erase pipeline, in a pass of their own after the overlay pass read the overlay
    /// (`passes::overlay_erase`). `None` where the pass draws into no overlay.
    fn blended_eraser(
        &self,
        frame: &FrameInputs,
        group: FrameGroup,
        list: SceneDrawList,
    ) -> Option<OverlayEraser> {
        let (program, pipeline) = self.pipelines.erase.clone()?;
        let (scene, instances) = (Arc::clone(&frame.scene), Arc::clone(&frame.instances));
        Some(Box::new(move |graph, overlay| {
            let mut pass = graph.add_pass("erase blended");
            group.read_by(&mut pass);
            if let BlendedDraws::Sorted { args, .. } = &list.blended {
                pass.read_buffer(*args, BufferAccess::Indirect);
            }
            pass.write_texture(overlay, TextureAccess::ColorAttachment);
            let overlay = *overlay;
            pass.execute(move |ctx| {
                let Some(group0) = group.bind_group(ctx, (&program, None), "overlay erase") else {
                    return;
                };
                let view = ctx.texture(overlay).create_view(&Default::default());
                let load = wgpu::LoadOp::Load;
                let mut pass = color_pass(&mut ctx.encoder, "erase blended", &view, load);
                pass.set_bind_group(0, &group0, &[]);
                let mut draws =
                    SceneDraws::new(&mut pass, &scene, &instances, VertexStreams::Forward);
                let materials = Some(scene.material_group());
                draw_blended(&mut draws, (&list, &instances), &pipeline, materials);
            });
        }))
    }

    /// The recording function of one frame.
    fn recorder(
        &self,
        frame: &FrameInputs,
        targets: Targets,
        group: FrameGroup,
        list: SceneDrawList,
    ) -> impl FnOnce(&mut crate::graph::PassContext<'_>) + 'static {
        let pipelines = Arc::clone(&self.pipelines);
        let (scene, instances) = (Arc::clone(&frame.scene), Arc::clone(&frame.instances));
        let sky = sky_color(frame.config.sky);
        move |ctx| {
            let Some(bound) = pipelines.opaque.bind(ctx, &scene, &group, "forward frame") else {
                return;
            };
            let Some(frame_group) = bound.gltf_group0() else {
                return;
            };
            let depth_view = ctx.texture(targets.depth).create_view(&Default::default());
            let color_view = ctx.texture(targets.color).create_view(&Default::default());
            let resolve_view = targets
                .resolve
                .map(|h| ctx.texture(h).create_view(&Default::default()));
            let load = match targets.layer {
                Layer::Scene => wgpu::LoadOp::Clear(sky),
                Layer::OverInPlace => wgpu::LoadOp::Load,
                // Transparent where the last frame's erasers drew (`passes::overlay_erase`).
                Layer::Overlay => wgpu::LoadOp::Load,
            };
            let mut pass = ctx.encoder.begin_render(&wgpu::RenderPassDescriptor {
                label: Some("forward"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &color_view,
                    depth_slice: None,
                    resolve_target: resolve_view.as_ref(),
                    ops: wgpu::Operations {
                        load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    // After a pre-pass no pipeline of this pass writes depth: attached
                    // read-only, the pass neither stores nor decompresses it.
                    depth_ops: (!targets.prepass).then_some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, frame_group, &[]);
            // Over a deferred image only the blended surfaces are left to draw.
            let opaque = targets.layer == Layer::Scene;
            draw_scene(
                &mut pass,
                (&scene, &instances),
                &list,
                (&pipelines, &bound),
                opaque,
            );
        }
    }
}

/// Records the scene into the forward pass: with `opaque`, the opaque and masked batches of
/// `list`; then its blended draws back to front (one multi-draw where they were ordered on
/// the GPU).
fn draw_scene<'a>(
    pass: &mut wgpu::RenderPass<'a>,
    (scene, instances): (&'a PreparedScene, &'a InstanceTable),
    list: &'a SceneDrawList,
    (pipelines, bound): (&'a ForwardPipelines, &'a BoundPrograms),
    opaque: bool,
) {
    let mut draws = SceneDraws::new(pass, scene, instances, VertexStreams::Forward);
    let materials = Some(scene.material_group());
    if opaque {
        let group2 = scene.material_group();
        draws.draw_batches_with(list, instances, |batch| {
            bound.state(&pipelines.opaque, batch, group2)
        });
        // The blended draws are glTF PBR's.
        if let Some(group0) = bound.gltf_group0() {
            draws.set_program_groups(group0, None);
        }
    }
    draw_blended(&mut draws, (list, instances), &pipelines.blended, materials);
}

/// Records `list`'s blended draws with `pipeline` (the blended one, or the overlay's erase),
/// back to front (one multi-draw where they were ordered on the GPU).
fn draw_blended<'a>(
    draws: &mut SceneDraws<'_, 'a>,
    (list, instances): (&'a SceneDrawList, &InstanceTable),
    pipeline: &'a wgpu::RenderPipeline,
    materials: Option<&'a wgpu::BindGroup>,
) {
    match &list.blended {
        BlendedDraws::Sorted {
            args_buffer,
            count,
            count_buffer,
            ..
        } => {
            // Where the opaque batches drew with counts, the blended draws do too: Mesa's
            // lavapipe (25.0) keeps a count-draw's count buffer for the next plain indirect
            // draw of the pass, which then draws only as many as that count says.
            if list.counts.is_some() {
                draws.multi_draw_count(
                    (pipeline, materials),
                    args_buffer,
                    0,
                    (count_buffer, 0),
                    *count,
                )
            } else {
                draws.multi_draw(pipeline, materials, args_buffer, 0, *count)
            }
        }
        BlendedDraws::Listed(blended) => {
            for &d in blended.iter() {
                let geometry = instances.draws[d as usize].geometry;
                draws.draw(pipeline, materials, geometry, d);
            }
        }
    }
}

/// The HDR clear colour where no surface is drawn.
fn sky_color(sky: glam::Vec3) -> wgpu::Color {
    wgpu::Color {
        r: f64::from(sky.x),
        g: f64::from(sky.y),
        b: f64::from(sky.z),
        a: 1.0,
    }
}
