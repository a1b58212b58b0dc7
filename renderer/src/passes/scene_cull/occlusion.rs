//! Occlusion culling's second phase, between the two halves of pre-Z (of the visibility raster
//! on the visibility path): a depth pyramid of what the first phase drew
//! (`shaders_gen::culling::occlusion`), then every slot in the frustum tested against it. The
//! slots found visible that the first phase left out are drawn by the late half
//! ([`crate::passes::prez::PrezPass::late`], [`crate::passes::visibility::VisRasterPass::late`]);
//! every pass after it draws the slots of either phase; and the verdicts are the first phase's
//! history next frame.
//!
//! The pass adds nothing when scene culling publishes no second phase (culling or occlusion
//! culling off, a device that cannot draw indirectly).

use crate::frame_data::ConfigError;
use shaders_gen::culling::{
    depth_pyramid_reduce, depth_pyramid_seed,
    occlusion_cull::{self, Frustum, OcclusionParams},
};

use crate::GpuContext;
use crate::frame_data::{
    FrameInputs, FrameResources, OcclusionDraws, OcclusionPacked, RenderError, RendererConfig,
    SceneDrawList, VisibilitySamples,
};
use crate::graph::{
    Buffer, BufferAccess, Handle, ImportAccess, RenderGraph, Texture, TextureAccess,
};
use crate::passes::{Pass, groups_8x8};
use crate::shader::ShaderProgram;

/// The pyramid's format: one 32-bit float per texel, the farthest depth it covers.
const PYRAMID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// The occlusion-culling pass.
#[derive(Debug)]
pub struct OcclusionCullPass {
    seed: (ShaderProgram, wgpu::ComputePipeline),
    reduce: (ShaderProgram, wgpu::ComputePipeline),
    cull: (ShaderProgram, wgpu::ComputePipeline),
    params: wgpu::Buffer,
    /// The pyramid of the current frame size.
    pyramid: Option<Pyramid>,
    /// The seed reads the compute rasteriser's samples, not a depth buffer
    /// ([`RendererConfig::reads_compute_samples`]), with the frame's size from this uniform.
    samples_frame: Option<wgpu::Buffer>,
}

/// A depth pyramid: level 0 half the frame on each axis (rounding up) and then up to a power
/// of two, so that every level above, half the one below, covers the whole frame too (texel
/// `t` of level `l` covers pixels `t·2^(l+1)` to `(t+1)·2^(l+1) − 1`; texels past the frame
/// repeat its last pixels), down to 1×1.
#[derive(Debug)]
struct Pyramid {
    frame: (u32, u32),
    texture: wgpu::Texture,
    /// One view per level, and the whole chain.
    levels: Vec<wgpu::TextureView>,
    whole: wgpu::TextureView,
    /// `reduce` bind groups: level `k` from level `k - 1`, for `k` from 1.
    reduce_groups: Vec<wgpu::BindGroup>,
}

impl Pyramid {
    fn new(
        device: &wgpu::Device,
        reduce: &ShaderProgram,
        frame: (u32, u32),
    ) -> Result<Self, shader_bind::BindError> {
        let half = |side: u32| side.div_ceil(2).max(1).next_power_of_two();
        let size = (half(frame.0), half(frame.1));
        let levels = 32 - size.0.max(size.1).leading_zeros();
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("depth pyramid"),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: levels,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: PYRAMID_FORMAT,
            // COPY_SRC: tools and tests read it back (`OcclusionCullPass::read_pyramid`).
            usage: wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let views: Vec<wgpu::TextureView> = (0..levels)
            .map(|level| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some("depth pyramid level"),
                    base_mip_level: level,
                    mip_level_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let reduce_groups = views
            .windows(2)
            .map(|pair| {
                depth_pyramid_reduce::Group0 {
                    below: &pair[0],
                    level: &pair[1],
                }
                .bind_group(
                    device,
                    reduce.layout(0),
                    reduce.variant,
                    "depth pyramid reduce",
                )
            })
            .collect::<Result<_, _>>()?;
        Ok(Self {
            frame,
            whole: texture.create_view(&Default::default()),
            texture,
            levels: views,
            reduce_groups,
        })
    }

    /// Texels of `level` on each axis.
    fn level_size(&self, level: u32) -> (u32, u32) {
        let s = self
            .texture
            .size()
            .mip_level_size(level, wgpu::TextureDimension::D2);
        (s.width, s.height)
    }
}

impl OcclusionCullPass {
    pub fn new(gpu: &GpuContext, config: &RendererConfig) -> Result<Self, RenderError> {
        let device = gpu.device();
        let caps = gpu.capabilities();
        let compute = |variant, entry: &str| -> Result<_, RenderError> {
            let program = gpu.program(variant)?;
            let pipeline = program.compute_pipeline(device, entry)?;
            Ok((program, pipeline))
        };
        let msaa = depth_pyramid_seed::Msaa::from_value(config.msaa).ok_or(RenderError::Config(
            ConfigError::SampleCount {
                asked: config.msaa,
                supported: caps.msaa_counts(),
            },
        ))?;
        let vis64 = config.reads_compute_samples();
        let seed_key = depth_pyramid_seed::VariantKey { msaa, vis64 };
        Ok(Self {
            seed: compute(depth_pyramid_seed::variant(seed_key), "seed")?,
            reduce: compute(
                depth_pyramid_reduce::variant(depth_pyramid_reduce::VariantKey::ALL[0]),
                "reduce",
            )?,
            cull: compute(
                occlusion_cull::variant(occlusion_cull::VariantKey::ALL[0]),
                "cull_occlusion",
            )?,
            params: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("occlusion cull params"),
                size: size_of::<OcclusionParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            pyramid: None,
            samples_frame: vis64.then(|| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("depth pyramid frame"),
                    size: size_of::<depth_pyramid_seed::SeedFrame>() as u64,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            }),
        })
    }
}

/// One level of the depth pyramid as read back: `width` × `height` texels, row by row.
#[derive(Debug, Clone, PartialEq)]
#[cfg(any(test, feature = "internals"))]
pub struct PyramidLevel {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<f32>,
}

impl OcclusionCullPass {
    /// The depth pyramid of the newest frame, level 0 first (blocking: tools and tests); empty
    /// before the first frame.
    #[cfg(any(test, feature = "internals"))]
    pub fn read_pyramid(&self, gpu: &GpuContext) -> Result<Vec<PyramidLevel>, RenderError> {
        let Some(pyramid) = &self.pyramid else {
            return Ok(Vec::new());
        };
        (0..pyramid.levels.len() as u32)
            .map(|level| {
                let bytes = crate::readback::read_texture_level(
                    gpu.device(),
                    gpu.queue(),
                    &pyramid.texture,
                    level,
                )?;
                let (width, height) = pyramid.level_size(level);
                Ok(PyramidLevel {
                    width,
                    height,
                    texels: bytemuck::pod_collect_to_vec(&bytes),
                })
            })
            .collect()
    }
}

/// Workgroups of 8×8 over `size`.
impl Pass for OcclusionCullPass {
    fn name(&self) -> &'static str {
        "occlusion culling"
    }

    fn prepare(&mut self, frame: &FrameInputs) -> Result<(), RenderError> {
        let size = (frame.config.width, frame.config.height);
        if self.pyramid.as_ref().is_none_or(|p| p.frame != size) {
            self.pyramid = Some(Pyramid::new(frame.gpu.device(), &self.reduce.0, size)?);
        }
        Ok(())
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let Some(mut list) = resources.scene_draws.clone() else {
            return Ok(());
        };
        let Some(mut occlusion) = list.occlusion.clone() else {
            return Ok(());
        };
        let missing = |input| {
            RenderError::Config(ConfigError::MissingInput {
                pass: "occlusion culling",
                input,
            })
        };
        // Under the compute rasteriser the depths are its samples (its first half and the
        // masked draws of the first phase): the frame need not resolve a depth target.
        let source = match &self.samples_frame {
            Some(uniform) => match resources.visibility.as_ref().map(|v| v.samples) {
                Some(VisibilitySamples::Buffer { samples }) => {
                    let c = &frame.config;
                    let size = depth_pyramid_seed::SeedFrame::new(
                        glam::UVec2::new(c.width, c.height),
                        glam::UVec2::ZERO,
                    );
                    frame
                        .gpu
                        .queue()
                        .write_buffer(uniform, 0, bytemuck::bytes_of(&size));
                    SeedSource::Samples(samples, uniform.clone())
                }
                _ => return Err(missing("the compute rasteriser's samples")),
            },
            None => SeedSource::Depth(resources.depth.ok_or(missing("the pre-Z depth"))?),
        };
        let pyramid = self
            .pyramid
            .as_ref()
            .ok_or(missing("the depth pyramid (prepare)"))?;
        self.write_params(frame, pyramid, &occlusion);
        let mut texture = resources.import_texture(
            graph,
            "depth pyramid",
            &pyramid.texture,
            ImportAccess::ReadWrite,
        );
        self.add_pyramid(graph, pyramid, source, &mut texture);
        self.add_late_cull(graph, frame, pyramid, texture, &list, &mut occlusion)?;
        // From here on the passes draw every slot either phase drew.
        list.args = occlusion.all;
        list.args_buffer = occlusion.all_buffer.clone();
        list.slot_args = occlusion.all_buffer.clone();
        list.counts = None;
        if let Some(packed) = occlusion.packed.as_mut() {
            add_late_compaction(graph, &mut occlusion.late, &mut occlusion.all, packed);
            list.args = packed.all;
            list.args_buffer = packed.all_args.clone();
            list.counts = Some(packed.all_counts.clone());
        }
        list.occlusion = Some(occlusion);
        resources.scene_draws = Some(list);
        Ok(())
    }
}

impl OcclusionCullPass {
    /// The test's view, frame, pyramid and slots.
    fn write_params(&self, frame: &FrameInputs, pyramid: &Pyramid, occlusion: &OcclusionDraws) {
        let camera = &frame.camera;
        let [left, right, bottom, top, near, far] = camera.frustum_planes();
        let params = OcclusionParams::new(
            camera.projection * camera.view,
            Frustum::new(left, right, bottom, top, near, far),
            frame.screen(),
            pyramid.levels.len() as u32,
            occlusion.slot_count,
            occlusion.slack,
            0,
            0,
            0,
        );
        frame
            .gpu
            .queue()
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
    }

    /// The pyramid from `source` into `texture`: level 0, then each level from the one below.
    fn add_pyramid(
        &self,
        graph: &mut RenderGraph,
        pyramid: &Pyramid,
        source: SeedSource,
        texture: &mut Handle<Texture>,
    ) {
        let seed_pipeline = self.seed.1.clone();
        let seed = self.seed.0.clone();
        let level0 = pyramid.levels[0].clone();
        let reduce_pipeline = self.reduce.1.clone();
        let reduces: Vec<(wgpu::BindGroup, (u32, u32))> = pyramid
            .reduce_groups
            .iter()
            .enumerate()
            .map(|(k, g)| (g.clone(), groups_8x8(pyramid.level_size(k as u32 + 1))))
            .collect();
        let seed_groups = groups_8x8(pyramid.level_size(0));
        let mut pass = graph.add_pass("depth pyramid");
        match &source {
            SeedSource::Depth(depth) => pass.read_texture(*depth, TextureAccess::Sampled),
            SeedSource::Samples(samples, _) => {
                pass.read_buffer(*samples, BufferAccess::StorageRead)
            }
        };
        pass.write_texture(texture, TextureAccess::StorageWrite)
            .execute(move |ctx| {
                let depth_view = match &source {
                    SeedSource::Depth(depth) => {
                        Some(ctx.texture(*depth).create_view(&Default::default()))
                    }
                    SeedSource::Samples(..) => None,
                };
                let (samples, frame) = match &source {
                    SeedSource::Samples(samples, frame) => (
                        Some(ctx.buffer(*samples).as_entire_buffer_binding()),
                        Some(frame.as_entire_buffer_binding()),
                    ),
                    SeedSource::Depth(_) => (None, None),
                };
                let built = depth_pyramid_seed::Group0 {
                    depth: depth_view.as_ref(),
                    depth_ms: depth_view.as_ref(),
                    vis64: samples,
                    frame,
                    level: &level0,
                }
                .bind_group(
                    ctx.device,
                    seed.layout(0),
                    seed.variant,
                    "depth pyramid seed",
                );
                let Some(seed_group) = ctx.bind(built) else {
                    return;
                };
                let mut pass = ctx.encoder.begin_compute("depth pyramid");
                pass.set_pipeline(&seed_pipeline);
                pass.set_bind_group(0, &seed_group, &[]);
                pass.dispatch_workgroups(seed_groups.0, seed_groups.1, 1);
                pass.set_pipeline(&reduce_pipeline);
                for (group, (x, y)) in &reduces {
                    pass.set_bind_group(0, group, &[]);
                    pass.dispatch_workgroups(*x, *y, 1);
                }
            });
    }

    /// Every slot against the pyramid, into the late and both-phases arguments.
    fn add_late_cull(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        pyramid: &Pyramid,
        texture: Handle<Texture>,
        list: &SceneDrawList,
        occlusion: &mut OcclusionDraws,
    ) -> Result<(), RenderError> {
        let program = &self.cull.0;
        let group = occlusion_cull::Group0 {
            params: self.params.as_entire_buffer_binding(),
            boxes: occlusion.boxes.as_entire_buffer_binding(),
            slot_draws: occlusion.slot_draws.as_entire_buffer_binding(),
            early_args: occlusion.first_buffer.as_entire_buffer_binding(),
            late_args: occlusion.late_buffer.as_entire_buffer_binding(),
            final_args: occlusion.all_buffer.as_entire_buffer_binding(),
            history: occlusion.history.as_entire_buffer_binding(),
            visible: occlusion.visible.as_entire_buffer_binding(),
            pyramid: &pyramid.whole,
        }
        .bind_group(
            frame.gpu.device(),
            program.layout(0),
            program.variant,
            "occlusion cull",
        )?;
        let pipeline = self.cull.1.clone();
        let workgroups = occlusion.slot_count.div_ceil(occlusion_cull::WORKGROUP);
        graph
            .add_pass("scene culling (late)")
            .read_texture(texture, TextureAccess::Sampled)
            .read_buffer(list.args, BufferAccess::StorageRead)
            .write_buffer(&mut occlusion.late, BufferAccess::StorageWrite)
            .write_buffer(&mut occlusion.all, BufferAccess::StorageWrite)
            .execute(move |ctx| {
                let mut pass = ctx.encoder.begin_compute("scene culling (late)");
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, &group, &[]);
                pass.dispatch_workgroups(workgroups, 1, 1);
            });
        Ok(())
    }
}

/// Packs the late and both-phases lists (compaction lists 1 and 2) after the late cull wrote
/// them.
fn add_late_compaction(
    graph: &mut RenderGraph,
    late: &mut Handle<Buffer>,
    all: &mut Handle<Buffer>,
    packed: &mut OcclusionPacked,
) {
    let record = std::sync::Arc::clone(&packed.record);
    graph
        .add_pass("scene draw compaction (late)")
        .read_buffer(*late, BufferAccess::StorageRead)
        .read_buffer(*all, BufferAccess::StorageRead)
        .write_buffer(&mut packed.late, BufferAccess::StorageWrite)
        .write_buffer(&mut packed.all, BufferAccess::StorageWrite)
        .execute(move |ctx| record(&mut ctx.encoder));
}

/// What the depth pyramid's level 0 is made from.
enum SeedSource {
    /// The depth buffer.
    Depth(Handle<Texture>),
    /// The compute rasteriser's samples, and the seed's frame-size uniform.
    Samples(Handle<Buffer>, wgpu::Buffer),
}
