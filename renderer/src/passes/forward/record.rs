//! Recording the forward pass: its render pass over the frame's targets, the scene's opaque
//! and masked batches and its blended draws back to front, and the eraser of the blended draws
//! drawn into an overlay (`passes::overlay_erase`).

use std::sync::Arc;

use super::over_samples::{FrameSamples, LISTED_DRAWS_AT, SHADED_DRAWS_AT};
use super::programs::BoundPrograms;
use super::{Depth, ForwardPass, ForwardPipelines, Layer, Targets};
use crate::frame_data::{
    BlendedDraws, FrameInputs, InstanceTable, OverlayEraser, PreparedScene, SceneDrawList,
};
use crate::graph::{BufferAccess, TextureAccess};
use crate::passes::forward::FrameGroup;
use crate::passes::{SceneDraws, color_pass};
use crate::scene::VertexStreams;

impl ForwardPass {
    /// The eraser of the blended draws this frame draws into the overlay: the same draws with
    /// the erase pipeline, in a pass of their own after the overlay pass read the overlay
    /// (`passes::overlay_erase`). `None` where the pass draws into no overlay.
    pub(super) fn blended_eraser(
        &self,
        frame: &FrameInputs,
        (group, samples): (FrameGroup, Option<FrameSamples>),
        list: SceneDrawList,
    ) -> Option<OverlayEraser> {
        let (program, pipeline) = self.pipelines.erase.clone()?;
        let (scene, instances) = (Arc::clone(&frame.scene), Arc::clone(&frame.instances));
        Some(Box::new(move |graph, overlay| {
            let mut pass = graph.add_pass("erase blended");
            group.read_by(&mut pass);
            if let Some(samples) = &samples {
                samples.read_by(&mut pass);
            }
            if let BlendedDraws::Sorted { args, .. } = &list.blended {
                pass.read_buffer(*args, BufferAccess::Indirect);
            }
            pass.write_texture(overlay, TextureAccess::ColorAttachment);
            let overlay = *overlay;
            pass.execute(move |ctx| {
                let group0 = match &samples {
                    Some(samples) => samples.bind_group(ctx, &group, &program),
                    None => group.bind_group(ctx, (&program, None), "overlay erase"),
                };
                let Some(group0) = group0 else {
                    return;
                };
                let view = ctx.texture(overlay).create_view(&Default::default());
                let load = wgpu::LoadOp::Load;
                let mut pass = color_pass(&mut ctx.encoder, "erase blended", &view, load);
                pass.set_bind_group(0, &group0, &[]);
                let mut draws =
                    SceneDraws::new(&mut pass, &scene, &instances, VertexStreams::Forward);
                // Over the compute rasteriser's samples the program's groups are its own.
                let materials = match &samples {
                    Some(samples) => {
                        samples.draws.bind(&mut draws, &group0);
                        &samples.draws.materials
                    }
                    None => scene.material_group(),
                };
                draw_blended(&mut draws, (&list, &instances), &pipeline, Some(materials));
            });
        }))
    }

    /// The recording function of one frame.
    pub(super) fn recorder(
        &self,
        frame: &FrameInputs,
        targets: Targets,
        (group, samples): (FrameGroup, Option<FrameSamples>),
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
            let blended_group = match &samples {
                Some(s) => match s.bind_group(ctx, &group, &pipelines.blended_program) {
                    Some(g) => Some((g, s)),
                    None => return,
                },
                None => None,
            };
            let depth_view = match targets.depth {
                Depth::Prepass(h) | Depth::Own(h) => {
                    Some(ctx.texture(h).create_view(&Default::default()))
                }
                Depth::None => None,
            };
            let prepass = matches!(targets.depth, Depth::Prepass(_));
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
                depth_stencil_attachment: depth_view.as_ref().map(|view| {
                    wgpu::RenderPassDepthStencilAttachment {
                        view,
                        // After a pre-pass no pipeline of this pass writes depth: attached
                        // read-only, the pass neither stores nor decompresses it.
                        depth_ops: (!prepass).then_some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(1.0),
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops: None,
                    }
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, frame_group, &[]);
            // Over a deferred image only the blended surfaces are left to draw.
            let opaque = targets.layer == Layer::Scene;
            let blended = blended_group.as_ref().map(|(g, d)| (g, *d));
            draw_scene(
                &mut pass,
                (&scene, &instances),
                &list,
                (&pipelines, &bound, blended),
                opaque,
            );
        }
    }
}

/// Records the scene into the forward pass: with `opaque`, the opaque and masked batches of
/// `list`; then its blended draws back to front (one multi-draw where they were ordered on
/// the GPU), with glTF PBR's groups, or, over the compute rasteriser's samples, the blended
/// program's group 0 and the frame's `FrameSamples` (none where the frame has no blended
/// draws): there, where the device counts draws, through both blended pipelines with the
/// counts `vis_blend_args` wrote (one of them draws nothing), else through the one that may
/// shade.
fn draw_scene<'a>(
    pass: &mut wgpu::RenderPass<'a>,
    (scene, instances): (&'a PreparedScene, &'a InstanceTable),
    list: &'a SceneDrawList,
    (pipelines, bound, blended): (
        &'a ForwardPipelines,
        &'a BoundPrograms,
        Option<(&'a wgpu::BindGroup, &'a FrameSamples)>,
    ),
    opaque: bool,
) {
    let mut draws = SceneDraws::new(pass, scene, instances, VertexStreams::Forward);
    let materials = Some(scene.material_group());
    if opaque {
        let group2 = scene.material_group();
        draws.draw_batches_with(list, instances, |batch| {
            bound.state(&pipelines.opaque, batch, group2)
        });
    }
    // The blended draws are glTF PBR's.
    match (blended, &pipelines.listed) {
        (Some((group0, samples)), Some(listed)) => {
            samples.draws.bind_pulled(&mut draws, group0);
            let materials = Some(&samples.draws.materials);
            match (&list.blended, list.counts.is_some()) {
                (
                    BlendedDraws::Sorted {
                        args_buffer, count, ..
                    },
                    true,
                ) => {
                    let counts = samples.draw_counts();
                    for (pipeline, at) in [
                        (listed, LISTED_DRAWS_AT),
                        (&pipelines.blended, SHADED_DRAWS_AT),
                    ] {
                        let drawn = (counts, at);
                        draws.multi_draw_count(
                            (pipeline, materials),
                            args_buffer,
                            0,
                            drawn,
                            *count,
                        );
                    }
                }
                _ => draw_blended(&mut draws, (list, instances), &pipelines.blended, materials),
            }
        }
        (None, None) => {
            if let Some(group0) = bound.gltf_group0() {
                draws.set_program_groups(group0, None);
            }
            draw_blended(&mut draws, (list, instances), &pipelines.blended, materials);
        }
        // Over the compute rasteriser's samples without blended draws: nothing to draw.
        _ => {}
    }
}

/// Records `list`'s blended draws with `pipeline` (the blended one, or the overlay's erase),
/// back to front (one multi-draw where they were ordered on the GPU).
pub(super) fn draw_blended<'a>(
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
