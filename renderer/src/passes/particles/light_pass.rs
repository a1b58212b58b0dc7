//! The particle lighting pass: `particle_light` lights every atlas texel in use this frame (an
//! indirect dispatch sized by the layout), then the texels are copied into the
//! `Rg11b10Ufloat` atlas the draw samples. It runs after light culling and the shadow atlas,
//! and only when particles are lit through the atlas.

use crate::frame_data::ConfigError;
use shaders_gen::particles::{particle_light, particle_lighting};

use crate::GpuContext;
use crate::frame_data::{
    FrameInputs, FrameResources, LightListHandles, RenderError, RendererConfig,
};
use crate::graph::{BufferAccess, ImportAccess, RenderGraph, TextureAccess};
use crate::passes::Pass;
use crate::shader::ShaderProgram;

/// The particle atlas lighting pass.
#[derive(Debug)]
pub struct ParticleLightPass {
    program: ShaderProgram,
    pipeline: wgpu::ComputePipeline,
}

impl ParticleLightPass {
    pub fn new(gpu: &GpuContext, config: &RendererConfig) -> Result<Self, RenderError> {
        let key = particle_light::VariantKey {
            list: if config.path.is_culled() {
                particle_light::List::List2
            } else {
                particle_light::List::List0
            },
        };
        let program = gpu.program(particle_light::variant(key))?;
        Ok(Self {
            pipeline: program.compute_pipeline(gpu.device(), "light_atlas")?,
            program,
        })
    }
}

impl Pass for ParticleLightPass {
    fn name(&self) -> &'static str {
        "particle lighting"
    }

    #[allow(
        clippy::too_many_lines,
        reason = "declares its reads, then binds, dispatches and copies in one recording"
    )]
    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let missing = |input| {
            RenderError::Config(ConfigError::MissingInput {
                pass: "particle lighting",
                input,
            })
        };
        let Some(particles) = resources.particles.clone() else {
            return Ok(());
        };
        let lists = resources.particle_lists.clone();
        if frame.config.path.is_culled() && lists.is_none() {
            return Err(missing("particle light lists"));
        }
        let shadows = resources.shadows.clone().ok_or(missing("shadow atlas"))?;
        let mut atlas = resources.import_texture(
            graph,
            "particle lighting atlas",
            &particles.atlas_texture,
            ImportAccess::ReadWrite,
        );
        let mut pass = graph.add_pass(self.name());
        pass.read_buffer(particles.simulated, BufferAccess::StorageRead)
            .read_buffer(particles.laid_out, BufferAccess::StorageRead)
            .read_texture(shadows.atlas, TextureAccess::Sampled)
            .write_texture(&mut atlas, TextureAccess::CopyDst);
        LightListHandles::read_by(lists.as_ref(), &mut pass);
        let program = self.program.clone();
        let pipeline = self.pipeline.clone();
        let lights = std::sync::Arc::clone(&frame.lights);
        let p = particles.clone();
        pass.execute(move |ctx| {
            let frame_group = particle_light::Group0 {
                particle_lighting: particle_lighting::Group0 {
                    view: p.view.as_entire_buffer_binding(),
                },
                light_set: lights.bindings(),
                light_lists: LightListHandles::bindings(lists.as_ref(), ctx),
                shadow_atlas: shadows.bindings(),
            }
            .bind_group(
                ctx.device,
                program.layout(particle_light::Group0::GROUP),
                program.variant,
                "particle lighting frame",
            );
            let particle_group = particle_light::Group1 {
                emitters: p.emitters.as_entire_buffer_binding(),
                particles: p.particles.as_entire_buffer_binding(),
                state: p.state.as_entire_buffer_binding(),
                owners: p.owners.as_entire_buffer_binding(),
                lit: p.lit_texels.as_entire_buffer_binding(),
            }
            .bind_group(
                ctx.device,
                program.layout(particle_light::Group1::GROUP),
                program.variant,
                "particle lighting",
            );
            let (Some(frame_group), Some(particle_group)) =
                (ctx.bind(frame_group), ctx.bind(particle_group))
            else {
                return;
            };
            {
                let mut compute = ctx.encoder.begin_compute("particle lighting");
                compute.set_pipeline(&pipeline);
                compute.set_bind_group(0, &frame_group, &[]);
                compute.set_bind_group(1, &particle_group, &[]);
                compute.dispatch_workgroups_indirect(&p.state, super::atlas::DISPATCH_ARGS_OFFSET);
            }
            let side = p.atlas_side;
            ctx.encoder.copy_buffer_to_texture(
                wgpu::TexelCopyBufferInfo {
                    buffer: &p.lit_texels,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(side * 4),
                        rows_per_image: Some(side),
                    },
                },
                p.atlas_texture.as_image_copy(),
                wgpu::Extent3d {
                    width: side,
                    height: side,
                    depth_or_array_layers: 1,
                },
            );
        });
        if let Some(p) = resources.particles.as_mut() {
            p.lit_atlas = Some(atlas);
        }
        Ok(())
    }
}
