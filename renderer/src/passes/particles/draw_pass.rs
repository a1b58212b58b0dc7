//! The particle draw: camera-facing billboards, back to front (the sorted keys), blended over the
//! forward pass's HDR colour (its multisampled target under MSAA, resolved again; on the deferred
//! paths with MSAA, the multisampled overlay of blended surfaces laid over the image later),
//! depth tested
//! per sample by the pipeline against the pre-Z depth attached read-only, and faded against a copy
//! of it the shader samples (soft particles; sampling the attached depth itself would make its
//! end-of-pass store a write after the shader's read, a hazard Vulkan's synchronization
//! validation reports). On the compute rasteriser's frame
//! ([`RendererConfig::reads_compute_samples`]) the shader reads its samples instead and weighs
//! its colour by the share of the pixel's samples it is in front of (`fs_particle_vis64`): no
//! depth target is attached or copied. Lit from
//! the atlas or, on the reference path, per pixel with the same lights and shadows.

use crate::frame_data::ConfigError;
use shaders_gen::particles::particle_draw::{self, List, VariantKey};
use shaders_gen::particles::particle_lighting;

use std::sync::Arc;

use crate::GpuContext;
use crate::frame_data::{
    FrameInputs, FrameResources, HDR_FORMAT, LightListHandles, LightSet, OverlayEraser,
    ParticleLighting, ParticleResources, RenderError, RendererConfig, ShadowResources,
    VisibilitySamples,
};
use crate::graph::{
    Buffer, BufferAccess, Handle, PassBuilder, PassContext, RenderGraph, Texture, TextureAccess,
    TextureDesc, TimedPass,
};
use crate::passes::overlay_erase::EraseStage;
use crate::passes::{Pass, color_pass};
use crate::shader::ShaderProgram;

/// The particle draw pass.
#[derive(Debug)]
pub struct ParticleDrawPass {
    program: ShaderProgram,
    pipeline: wgpu::RenderPipeline,
    /// The variant's key: lit from the atlas, or per pixel over every light or the lists.
    key: VariantKey,
    /// On the deferred paths with MSAA, where the billboards go into the overlay: the
    /// pipeline that erases them (`passes::overlay_erase`).
    erase: Option<wgpu::RenderPipeline>,
}

impl ParticleDrawPass {
    pub fn new(gpu: &GpuContext, config: &RendererConfig) -> Result<Self, RenderError> {
        let atlas = config.particle_lighting == ParticleLighting::Atlas;
        let vis64 = config.reads_compute_samples();
        let key = VariantKey {
            atlas,
            list: if !atlas && config.path.is_culled() {
                List::List2
            } else {
                List::List0
            },
            msaa: config.msaa > 1 && !vis64,
            vis64,
        };
        let program = gpu.program(particle_draw::variant(key)?)?;
        let pipeline = pipeline(gpu.device(), &program, config.msaa, vis64);
        let erase = if config.path.is_deferred() && config.msaa > 1 {
            let stage = EraseStage::new(gpu)?;
            Some(stage.pipeline(gpu.device(), (&program, "vs_particle"), &[], config.msaa))
        } else {
            None
        };
        Ok(Self {
            program,
            pipeline,
            key,
            erase,
        })
    }
}

/// The draw's pipeline: testing the pre-Z depth attached read-only, or, for the `vis64`
/// variant, with no depth test (its `fs_particle_vis64` tests the compute rasteriser's
/// samples itself).
fn pipeline(
    device: &wgpu::Device,
    program: &ShaderProgram,
    msaa: u32,
    vis64: bool,
) -> wgpu::RenderPipeline {
    program.render_pipeline(
        device,
        &wgpu::RenderPipelineDescriptor {
            label: Some("particles"),
            layout: Some(&program.pipeline_layout),
            vertex: wgpu::VertexState {
                module: &program.module,
                entry_point: Some("vs_particle"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            // Per-sample occlusion by the pre-Z depth, attached read-only (and sampled for the fade).
            depth_stencil: (!vis64)
                .then(|| crate::passes::depth_state(false, wgpu::CompareFunction::Less)),
            multisample: wgpu::MultisampleState {
                count: msaa,
                ..Default::default()
            },
            fragment: Some(wgpu::FragmentState {
                module: &program.module,
                entry_point: Some(if vis64 {
                    "fs_particle_vis64"
                } else {
                    "fs_particle"
                }),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: HDR_FORMAT,
                    blend: Some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        },
    )
}

impl Pass for ParticleDrawPass {
    fn name(&self) -> &'static str {
        "particles"
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let missing = |input| {
            RenderError::Config(ConfigError::MissingInput {
                pass: "particles",
                input,
            })
        };
        let Some(particles) = resources.particles.clone() else {
            return Ok(());
        };
        let occluders = Occluders::of(graph, frame, resources, self.key.vis64)?;
        // With MSAA on the deferred paths, particles join the blended surfaces' multisampled
        // overlay (the overlay pass resolves it).
        let overlay = resources.hdr_overlay;
        let erase = match (overlay, self.erase.clone()) {
            (Some(_), None) => {
                return Err(missing(
                    "an erase pipeline for the overlay (built on the deferred paths with MSAA)",
                ));
            }
            (overlay, erase) => erase.filter(|_| overlay.is_some()),
        };
        let mut hdr = overlay.or(resources.hdr).ok_or(missing("HDR colour"))?;
        let mut multisampled = resources.hdr_multisampled.filter(|_| overlay.is_none());
        let shadows = resources.shadows.clone().ok_or(missing("shadow atlas"))?;
        let listed = self.key.list == List::List2;
        let lists = listed.then(|| resources.particle_lists.clone()).flatten();
        if listed && lists.is_none() {
            return Err(missing("particle light lists"));
        }
        let atlas = if self.key.atlas {
            Some(
                particles
                    .lit_atlas
                    .ok_or(missing("particle lighting atlas"))?,
            )
        } else {
            None
        };
        let inputs = DrawInputs {
            particles,
            lights: Arc::clone(&frame.lights),
            lists,
            occluders,
            shadows,
            atlas,
        };
        let mut pass = graph.add_pass(self.name());
        inputs.read_by(&mut pass);
        if let Some(attached) = occluders.attached() {
            pass.read_texture(attached, TextureAccess::DepthRead);
        }
        pass.write_texture(&mut hdr, TextureAccess::ColorAttachment);
        if let Some(m) = multisampled.as_mut() {
            pass.write_texture(m, TextureAccess::ColorAttachment);
        }
        let program = self.program.clone();
        let pipeline = self.pipeline.clone();
        let eraser = erase.map(|erase| inputs.clone().eraser(program.clone(), erase));
        pass.execute(move |ctx| {
            let Some(groups) = inputs.bind(ctx, &program) else {
                return;
            };
            let depth_view = (occluders.attached())
                .map(|attached| ctx.texture(attached).create_view(&Default::default()));
            let resolved = ctx.texture(hdr).create_view(&Default::default());
            let msaa_view = multisampled.map(|m| ctx.texture(m).create_view(&Default::default()));
            let targets = (&resolved, msaa_view.as_ref());
            let mut render = begin_particles(ctx, targets, depth_view.as_ref());
            inputs.draw(&mut render, &pipeline, (&groups.0, &groups.1));
        });
        if let Some(eraser) = eraser {
            resources.add_overlay_eraser(eraser);
        }
        if overlay.is_some() {
            resources.hdr_overlay = Some(hdr);
        } else {
            resources.hdr = Some(hdr);
        }
        resources.hdr_multisampled = multisampled;
        Ok(())
    }
}

/// A copy of the pre-Z `depth` for the shader's fade (sampling the attached depth itself would
/// be a hazard; see the module's doc).
fn fade_depth_copy(
    graph: &mut RenderGraph,
    depth: Handle<Texture>,
    c: &RendererConfig,
) -> Handle<Texture> {
    let mut fade_depth = graph.create_texture(
        "particle fade depth",
        TextureDesc::new_2d(c.width, c.height, crate::frame_data::DEPTH_FORMAT)
            .with_samples(c.msaa),
    );
    graph
        .add_pass("particle fade depth")
        .read_texture(depth, TextureAccess::CopySrc)
        .write_texture(&mut fade_depth, TextureAccess::CopyDst)
        .execute(move |ctx| {
            let from = ctx.texture(depth).clone();
            let to = ctx.texture(fade_depth).clone();
            ctx.encoder.copy_texture_to_texture(
                from.as_image_copy(),
                to.as_image_copy(),
                from.size(),
            );
        });
    fade_depth
}

/// The particles' render pass: over `resolved`, or over `multisampled` resolving into it, the
/// depth (where the pipeline tests one) attached read-only.
fn begin_particles<'e>(
    ctx: &'e mut PassContext<'_>,
    (resolved, multisampled): (&wgpu::TextureView, Option<&wgpu::TextureView>),
    depth: Option<&wgpu::TextureView>,
) -> TimedPass<'e, wgpu::RenderPass<'e>> {
    ctx.encoder.begin_render(&wgpu::RenderPassDescriptor {
        label: Some("particles"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: multisampled.unwrap_or(resolved),
            depth_slice: None,
            resolve_target: multisampled.map(|_| resolved),
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: depth.map(|view| wgpu::RenderPassDepthStencilAttachment {
            view,
            depth_ops: None,
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// What hides the particles.
#[derive(Clone, Copy)]
enum Occluders {
    /// The pre-Z depth, `attached` read-only for the pipeline's test, and its `copy`, which the
    /// shader samples for the fade.
    Depth {
        attached: Handle<Texture>,
        copy: Handle<Texture>,
    },
    /// The compute rasteriser's samples, which the `vis64` variant reads for both.
    Samples(Handle<Buffer>),
}

impl Occluders {
    /// This frame's: the compute rasteriser's samples for the `vis64` variant, else the depth
    /// target and a copy of it.
    fn of(
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &FrameResources,
        vis64: bool,
    ) -> Result<Self, RenderError> {
        let missing = |input| {
            RenderError::Config(ConfigError::MissingInput {
                pass: "particles",
                input,
            })
        };
        if vis64 {
            return match resources.visibility.as_ref().map(|v| v.samples) {
                Some(VisibilitySamples::Buffer { samples }) => Ok(Self::Samples(samples)),
                _ => Err(missing("the compute rasteriser's samples")),
            };
        }
        let attached = resources.depth.ok_or(missing("depth buffer"))?;
        let copy = fade_depth_copy(graph, attached, &frame.config);
        Ok(Self::Depth { attached, copy })
    }

    /// The depth target the pipeline tests, attached read-only.
    fn attached(self) -> Option<Handle<Texture>> {
        match self {
            Self::Depth { attached, .. } => Some(attached),
            Self::Samples(_) => None,
        }
    }
}

/// What one frame's particle draw binds, shared by the draw and its overlay eraser.
#[derive(Clone)]
struct DrawInputs {
    particles: ParticleResources,
    lights: Arc<LightSet>,
    lists: Option<LightListHandles>,
    occluders: Occluders,
    shadows: ShadowResources,
    atlas: Option<Handle<Texture>>,
}

impl DrawInputs {
    /// Declares what the bind groups read.
    fn read_by(&self, pass: &mut PassBuilder<'_>) {
        let p = &self.particles;
        pass.read_buffer(p.simulated, BufferAccess::StorageRead)
            .read_buffer(p.laid_out, BufferAccess::StorageRead)
            .read_texture(self.shadows.atlas, TextureAccess::Sampled);
        match self.occluders {
            Occluders::Depth { copy, .. } => pass.read_texture(copy, TextureAccess::Sampled),
            Occluders::Samples(samples) => pass.read_buffer(samples, BufferAccess::StorageRead),
        };
        if let Some(a) = self.atlas {
            pass.read_texture(a, TextureAccess::Sampled);
        }
        LightListHandles::read_by(self.lists.as_ref(), pass);
    }

    /// Groups 0 and 1 of `program`; `None` after recording the error in `ctx`.
    fn bind(
        &self,
        ctx: &mut PassContext<'_>,
        program: &ShaderProgram,
    ) -> Option<(wgpu::BindGroup, wgpu::BindGroup)> {
        let p = &self.particles;
        let (fade_view, samples) = match self.occluders {
            Occluders::Depth { copy, .. } => {
                let view = ctx.texture(copy).create_view(&wgpu::TextureViewDescriptor {
                    aspect: wgpu::TextureAspect::DepthOnly,
                    ..Default::default()
                });
                (Some(view), None)
            }
            Occluders::Samples(samples) => (None, Some(ctx.buffer(samples).clone())),
        };
        // The fade depth is given for both spellings; the variant binds the one its MSAA axis
        // declares.
        let frame_group = particle_draw::Group0 {
            particle_lighting: particle_lighting::Group0 {
                view: p.view.as_entire_buffer_binding(),
            },
            light_set: self.lights.bindings(),
            light_lists: LightListHandles::bindings(self.lists.as_ref(), ctx),
            depth: fade_view.as_ref(),
            depth_ms: fade_view.as_ref(),
            vis64: samples.as_ref().map(wgpu::Buffer::as_entire_buffer_binding),
            shadow_atlas: self.shadows.bindings(),
        }
        .bind_group(
            ctx.device,
            program.layout(particle_draw::Group0::GROUP),
            program.variant,
            "particles frame",
        );
        let atlas_view = self
            .atlas
            .map(|a| ctx.texture(a).create_view(&Default::default()));
        let particle_group = particle_draw::Group1 {
            emitters: p.emitters.as_entire_buffer_binding(),
            particles: p.particles.as_entire_buffer_binding(),
            regions: p.regions.as_entire_buffer_binding(),
            keys: p.keys.as_entire_buffer_binding(),
            light_atlas: atlas_view.as_ref(),
            atlas_sampler: atlas_view.as_ref().map(|_| &p.sampler),
            sprites: &p.sprites,
            sprite_sampler: &p.sampler,
        }
        .bind_group(
            ctx.device,
            program.layout(particle_draw::Group1::GROUP),
            program.variant,
            "particles",
        );
        Some((ctx.bind(frame_group)?, ctx.bind(particle_group)?))
    }

    /// The billboards, with `pipeline` (the draw's or the eraser's).
    fn draw(
        &self,
        render: &mut wgpu::RenderPass<'_>,
        pipeline: &wgpu::RenderPipeline,
        (frame_group, particle_group): (&wgpu::BindGroup, &wgpu::BindGroup),
    ) {
        render.set_pipeline(pipeline);
        render.set_bind_group(0, frame_group, &[]);
        render.set_bind_group(1, particle_group, &[]);
        render.draw_indirect(&self.particles.state, super::atlas::DRAW_ARGS_OFFSET);
    }

    /// The eraser of the billboards this frame draws into the overlay: the same draw with the
    /// erase pipeline `erase` of `program` (`passes::overlay_erase`).
    fn eraser(self, program: ShaderProgram, erase: wgpu::RenderPipeline) -> OverlayEraser {
        Box::new(move |graph, overlay| {
            let mut pass = graph.add_pass("erase particles");
            self.read_by(&mut pass);
            pass.write_texture(overlay, TextureAccess::ColorAttachment);
            let overlay = *overlay;
            pass.execute(move |ctx| {
                let Some(groups) = self.bind(ctx, &program) else {
                    return;
                };
                let view = ctx.texture(overlay).create_view(&Default::default());
                let load = wgpu::LoadOp::Load;
                let mut render = color_pass(&mut ctx.encoder, "erase particles", &view, load);
                self.draw(&mut render, &erase, (&groups.0, &groups.1));
            });
        })
    }
}
