//! The visibility path's shading pass: materials and lighting in compute, over the light lists,
//! writing the resolved HDR image. Each material program the scene names has its kernel (its
//! module's `vis_shade`, `shaders_gen::visibility::vis_frame` around its `surface`), which
//! shades its own triangles over the whole screen and passes the pixel sums on; glTF PBR's
//! (`shaders_gen::forward::forward`) runs last, adds the sky and writes the image.

use shaders_gen::forward::forward;
use shaders_gen::visibility::vis_frame;

use super::geometry::geometry_group;
use crate::GpuContext;
use crate::frame_data::{
    ConfigError, FrameInputs, FrameResources, FrameView, HDR_FORMAT, RenderError, RenderPath,
    RendererConfig, VisibilityHandles, VisibilitySamples,
};
use crate::graph::{
    Buffer, BufferAccess, BufferDesc, Handle, PassBuilder, RenderGraph, Texture, TextureAccess,
    TextureDesc,
};
use crate::materials::{MaterialError, MaterialProgram, PARAMS_GROUP, PARAMS_NAME};
use crate::passes::forward::bindings::{FrameGroup, VisInputs, VisSampleViews, lighting_buffer};
use crate::passes::{Pass, groups_8x8};
use crate::shader::ShaderProgram;

/// One material program's kernel.
#[derive(Debug)]
struct Kernel {
    /// Its module's name (what a scene's materials name).
    name: &'static str,
    program: ShaderProgram,
    pipeline: wgpu::ComputePipeline,
    /// Whether it binds parameter records (`PARAMS`).
    params: bool,
    /// Its `VisParams` uniform.
    uniform: wgpu::Buffer,
}

/// The visibility shading pass: glTF PBR's kernel and every registered material program's,
/// and the lighting uniform.
#[derive(Debug)]
pub struct VisShadePass {
    /// glTF PBR's first, then each registered program's.
    kernels: Vec<Kernel>,
    lighting: wgpu::Buffer,
}

impl VisShadePass {
    /// The pass for `config` and the registered `materials`: clustered lists (the path's),
    /// refused where the device binds fewer storage buffers per stage than a kernel reads.
    pub fn new(
        gpu: &GpuContext,
        config: &RendererConfig,
        materials: &[MaterialProgram],
    ) -> Result<Self, RenderError> {
        let msaa = forward::Msaa::from_value(config.msaa)
            .filter(|&m| m != forward::Msaa::Msaa0)
            .ok_or_else(|| {
                RenderError::Config(ConfigError::SampleCount {
                    asked: config.msaa,
                    supported: crate::materials::VIS_SAMPLE_COUNTS.to_vec(),
                })
            })?;
        // The compute rasteriser's frames read its buffer (`vis64`), the hardware's its targets.
        let vis64 = config.reads_compute_samples();
        let gltf = forward::variant(forward::VariantKey {
            list: forward::List::List2,
            blend: false,
            scalarize: config.scalarize,
            msaa,
            vis64,
        })?;
        let mut variants = vec![(forward::MODULE.name, gltf)];
        for m in materials {
            let variant = m
                .vis_variant(config.msaa, config.scalarize, vis64)
                .ok_or_else(|| MaterialError::MissingVariant {
                    module: m.name().to_string(),
                    variant: crate::materials::vis_variant_name(
                        config.msaa,
                        config.scalarize,
                        vis64,
                    ),
                })?;
            variants.push((m.name(), variant));
        }
        let mut kernels = Vec::with_capacity(variants.len());
        for (name, variant) in variants {
            check_storage_limit(gpu, variant)?;
            let program = gpu.program(variant)?;
            kernels.push(Kernel {
                name,
                pipeline: program.compute_pipeline(gpu.device(), "vis_shade")?,
                params: variant
                    .group(PARAMS_GROUP)
                    .any(|binding| binding.name == PARAMS_NAME),
                program,
                uniform: gpu.device().create_buffer(&wgpu::BufferDescriptor {
                    label: Some("visibility params"),
                    size: size_of::<vis_frame::VisParams>() as u64,
                    // COPY_SRC: tools read back what a kernel bound (the tests' host replay).
                    usage: wgpu::BufferUsages::UNIFORM
                        | wgpu::BufferUsages::COPY_DST
                        | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                }),
            });
        }
        Ok(Self {
            kernels,
            lighting: lighting_buffer(gpu.device()),
        })
    }

    /// glTF PBR's kernel's program (a tool records its bindings:
    /// `ShaderProgram::record_bindings`).
    #[cfg(any(test, feature = "internals"))]
    pub fn program(&self) -> &ShaderProgram {
        &self.kernels[0].program
    }
}

/// Refuses a kernel that binds more storage buffers per stage than the device allows.
fn check_storage_limit(
    gpu: &GpuContext,
    variant: &codegen::rt::Variant,
) -> Result<(), RenderError> {
    let storage = variant
        .bindings
        .iter()
        .filter(|b| matches!(b.kind, codegen::rt::BindingKind::Storage { .. }))
        .count() as u32;
    let max = gpu.device().limits().max_storage_buffers_per_shader_stage;
    if storage > max {
        return Err(RenderError::Config(ConfigError::PathNeedsLimit {
            path: RenderPath::Visibility,
            limit: "max_storage_buffers_per_shader_stage",
            needs: storage.into(),
            device: max.into(),
        }));
    }
    Ok(())
}

/// One kernel's dispatch of a frame: its program, pipeline and uniform, its parameter records
/// where it takes them, and its groups 1 to 3 (group 0 is built at recording, from the frame's
/// textures).
struct Dispatch {
    program: ShaderProgram,
    pipeline: wgpu::ComputePipeline,
    uniform: wgpu::Buffer,
    params: Option<wgpu::Buffer>,
    groups: [wgpu::BindGroup; 3],
}

impl VisShadePass {
    /// This frame's dispatches: each material program the scene names (in its program-number
    /// order) whose kernel this pass has, then glTF PBR's; each kernel's uniform written.
    fn dispatches(
        &self,
        frame: &FrameInputs,
        vis: &VisibilityHandles,
    ) -> Result<Vec<Dispatch>, RenderError> {
        let device = frame.gpu.device();
        let c = &frame.config;
        let cam = &frame.camera;
        let names: Vec<&str> = frame.scene.material_program_names().collect();
        let order = (1..=names.len() as u32).chain(std::iter::once(0));
        let mut out = Vec::new();
        for number in order {
            let name = match number {
                0 => forward::MODULE.name,
                n => names[n as usize - 1],
            };
            let Some(kernel) = self.kernels.iter().position(|k| k.name == name) else {
                // The renderer refuses materials of programs it has not registered.
                continue;
            };
            let k = &self.kernels[kernel];
            let records = match (k.params, frame.scene.material_params(number)) {
                (true, Some(buffer)) => Some(buffer.clone()),
                // A program whose materials hold no parameter records yet draws nothing.
                (true, None) => continue,
                (false, _) => None,
            };
            let uniform = vis_frame::VisParams::new(
                (cam.projection * cam.view).inverse(),
                c.sky,
                vis.draws,
                frame.screen(),
                u32::from(c.view == FrameView::ShadingFrequency),
                number,
                // Every kernel after the first adds to the sums the ones before left.
                u32::from(!out.is_empty()),
                0,
                glam::UVec2::ZERO,
            );
            frame
                .gpu
                .queue()
                .write_buffer(&k.uniform, 0, bytemuck::bytes_of(&uniform));
            out.push(Dispatch {
                program: k.program.clone(),
                pipeline: k.pipeline.clone(),
                uniform: k.uniform.clone(),
                params: records,
                groups: [
                    frame.instances.draw_group_for(device, &k.program)?,
                    frame.scene.material_group_for(device, &k.program)?,
                    geometry_group(device, &k.program, &frame.scene, &vis.draw_geometry)?,
                ],
            });
        }
        Ok(out)
    }
}

impl Pass for VisShadePass {
    fn name(&self) -> &'static str {
        "visibility shading"
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let missing = |input| {
            RenderError::Config(ConfigError::MissingInput {
                pass: "visibility shading",
                input,
            })
        };
        let c = &frame.config;
        let vis = resources
            .visibility
            .clone()
            .ok_or(missing("visibility buffer"))?;
        let lists = resources
            .light_lists
            .clone()
            .ok_or(missing("light lists"))?;
        let shadows = resources.shadows.clone().ok_or(missing("shadow atlas"))?;
        let dispatches = self.dispatches(frame, &vis)?;
        // The sums the kernels before glTF PBR's pass on: a vec4 a pixel where there are any.
        let pixels = if dispatches.len() > 1 {
            u64::from(c.width) * u64::from(c.height)
        } else {
            1
        };
        let mut sums = graph.create_buffer("visibility sums", BufferDesc { size: pixels * 16 });
        let mut hdr =
            graph.create_texture("hdr", TextureDesc::new_2d(c.width, c.height, HDR_FORMAT));
        // The hardware raster's IDs are read with its depth (1.0: sky, whatever the ID).
        let source = match vis.samples {
            VisibilitySamples::Targets { ids } => {
                let depth = resources.depth.ok_or(missing("depth"))?;
                Source::Targets { ids, depth }
            }
            VisibilitySamples::Buffer { samples } => Source::Buffer(samples),
        };
        let mut pass = graph.add_pass(self.name());
        source.read_by(&mut pass);
        pass.write_buffer(&mut sums, BufferAccess::StorageWrite)
            .write_texture(&mut hdr, TextureAccess::StorageWrite);
        let group = FrameGroup::new(frame, &self.lighting, Some(lists), shadows);
        group.read_by(&mut pass);
        let (width, height) = (c.width, c.height);
        pass.execute(move |ctx| {
            let samples = match source {
                Source::Targets { ids, depth } => VisSampleViews::Targets {
                    ids: ctx.texture(ids).create_view(&Default::default()),
                    depth: ctx.texture(depth).create_view(&Default::default()),
                },
                Source::Buffer(samples) => VisSampleViews::Buffer(ctx.buffer(samples).clone()),
            };
            let out = ctx.texture(hdr).create_view(&Default::default());
            let sums = ctx.buffer(sums).clone();
            let mut groups0 = Vec::with_capacity(dispatches.len());
            for d in &dispatches {
                let inputs = VisInputs {
                    params: &d.uniform,
                    samples: &samples,
                    out: &out,
                    sums: &sums,
                };
                let program = (&d.program, d.params.as_ref());
                let Some(group0) = group.vis_bind_group(ctx, program, &inputs) else {
                    return;
                };
                groups0.push(group0);
            }
            let mut pass = ctx.encoder.begin_compute("visibility shading");
            // Each dispatch reads the sums the one before wrote: wgpu orders them.
            for (d, group0) in dispatches.iter().zip(&groups0) {
                pass.set_pipeline(&d.pipeline);
                pass.set_bind_group(0, group0, &[]);
                for (index, g) in d.groups.iter().enumerate() {
                    pass.set_bind_group(index as u32 + 1, g, &[]);
                }
                let (x, y) = groups_8x8((width, height));
                pass.dispatch_workgroups(x, y, 1);
            }
        });
        resources.hdr = Some(hdr);
        resources.hdr_multisampled = None;
        Ok(())
    }
}

/// Where this frame's shading kernels read their samples (`VisibilitySamples`, with the
/// hardware raster's depth).
#[derive(Clone, Copy)]
enum Source {
    Targets {
        ids: Handle<Texture>,
        depth: Handle<Texture>,
    },
    Buffer(Handle<Buffer>),
}

impl Source {
    /// Declares `pass`'s reads of the samples.
    fn read_by(self, pass: &mut PassBuilder<'_>) {
        match self {
            Self::Targets { ids, depth } => {
                pass.read_texture(ids, TextureAccess::Sampled)
                    .read_texture(depth, TextureAccess::Sampled);
            }
            Self::Buffer(samples) => {
                pass.read_buffer(samples, BufferAccess::StorageRead);
            }
        }
    }
}
