//! The G-buffer pass of the deferred paths: opaque and alpha-masked surfaces drawn over the
//! pre-Z depth (`LessEqual`, no writes) through the `forward` module's `fs_gbuffer`, which
//! shares the forward fragment's material and decal code, into the three multisampled targets
//! of `GBUFFER_FORMATS`.
//!
//! The targets are loaded, not cleared: a sample no surface covers is sky, where the pre-Z depth
//! is 1.0, and every reader of the G-buffer tests that depth before it reads the targets (the
//! TBDR and deferred-base kernel's `tbdr_gbuffer`, the light volumes). Clearing them cost more
//! than drawing into them on the H200 (at MSAA 4, 3.5 of the pass's 6.15 ms on the courtyard;
//! BENCHMARKS.md).

use crate::frame_data::ConfigError;
use std::sync::Arc;

use crate::GpuContext;
use crate::frame_data::{
    FrameInputs, FrameResources, GBUFFER_FORMATS, GBufferHandles, RenderError, RendererConfig,
};
use crate::graph::{BufferAccess, RenderGraph, TextureAccess, TextureDesc};
use crate::graph::{PassEncoder, TimedPass};
use crate::materials::MaterialProgram;
use crate::passes::forward::{FrameGroup, MaterialPipelines, lighting_buffer};
use crate::passes::{MeshPipeline, Pass, SceneDraws, depth_state, mesh_pipeline};
use crate::scene::VertexStreams;

/// The G-buffer pass: programs (glTF PBR's and every registered material program's) for
/// decals from every decal (no lists this frame) and from the tiled lists, and the lighting
/// uniform.
#[derive(Debug)]
pub struct GBufferPass {
    programs: Arc<[MaterialPipelines; 2]>,
    lighting: wgpu::Buffer,
}

impl GBufferPass {
    /// The pass of `config`, with pipelines for glTF PBR and every program of `materials`.
    pub fn new(
        gpu: &GpuContext,
        config: &RendererConfig,
        materials: &[MaterialProgram],
    ) -> Result<Self, RenderError> {
        let make = |list| {
            MaterialPipelines::new(gpu, materials, (list, false, false), |program, d, m| {
                let targets = GBUFFER_FORMATS.map(|f| Some(f.into()));
                mesh_pipeline(
                    gpu.device(),
                    program,
                    &MeshPipeline {
                        label: "gbuffer",
                        vertex_entry: "vs_forward",
                        streams: &crate::passes::FORWARD_STREAMS,
                        double_sided: d,
                        mirrored: m,
                        depth: Some(depth_state(false, wgpu::CompareFunction::LessEqual)),
                        msaa: config.msaa,
                        fragment: Some(("fs_gbuffer", &targets)),
                    },
                )
            })
        };
        Ok(Self {
            programs: Arc::new([make(0)?, make(1)?]),
            lighting: lighting_buffer(gpu.device()),
        })
    }
}

impl Pass for GBufferPass {
    fn name(&self) -> &'static str {
        "gbuffer"
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let missing = |input| {
            RenderError::Config(ConfigError::MissingInput {
                pass: "gbuffer",
                input,
            })
        };
        let c = &frame.config;
        let depth = resources.depth.ok_or(missing("pre-Z depth"))?;
        let shadows = resources.shadows.clone().ok_or(missing("shadow atlas"))?;
        let lists = resources.light_lists.clone();
        let names = [
            "gbuffer albedo",
            "gbuffer normals",
            "gbuffer radiance",
            "gbuffer view depth",
        ];
        let mut targets = [0, 1, 2, 3].map(|i| {
            let desc =
                TextureDesc::new_2d(c.width, c.height, GBUFFER_FORMATS[i]).with_samples(c.msaa);
            graph.create_texture(names[i], desc)
        });
        let list = resources.scene_draws.clone().ok_or(RenderError::Config(
            ConfigError::MissingInput {
                pass: "gbuffer",
                input: "the scene's draw batches (scene culling)",
            },
        ))?;
        let mut pass = graph.add_pass(self.name());
        pass.read_texture(depth, TextureAccess::DepthRead)
            .read_buffer(list.args, BufferAccess::Indirect);
        for t in &mut targets {
            pass.write_texture(t, TextureAccess::ColorAttachment);
        }
        let programs = Arc::clone(&self.programs);
        let which = usize::from(lists.is_some());
        let group = FrameGroup::new(frame, &self.lighting, lists, shadows);
        group.read_by(&mut pass);
        let (scene, instances) = (Arc::clone(&frame.scene), Arc::clone(&frame.instances));
        pass.execute(move |ctx| {
            let p = &programs[which];
            let Some(bound) = p.bind(ctx, &scene, &group, "gbuffer") else {
                return;
            };
            let views = targets.map(|t| ctx.texture(t).create_view(&Default::default()));
            let depth_view = ctx.texture(depth).create_view(&Default::default());
            let mut pass = begin_gbuffer_pass(&mut ctx.encoder, &views, &depth_view);
            // The opaque and masked batches, as pre-Z and the forward pass draw them, each
            // with its material program.
            let mut draws = SceneDraws::new(&mut pass, &scene, &instances, VertexStreams::Forward);
            let group2 = scene.material_group();
            draws.draw_batches_with(&list, &instances, |batch| bound.state(p, batch, group2));
        });
        let [albedo, normals, radiance, view_depth] = targets;
        resources.gbuffer = Some(GBufferHandles {
            albedo,
            normals,
            radiance,
            view_depth,
        });
        Ok(())
    }
}

/// The G-buffer render pass: the four targets and the pre-Z depth loaded.
fn begin_gbuffer_pass<'e>(
    encoder: &'e mut PassEncoder<'_>,
    views: &[wgpu::TextureView; 4],
    depth: &wgpu::TextureView,
) -> TimedPass<'e, wgpu::RenderPass<'e>> {
    let attachments = views.each_ref().map(|view| {
        Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                // Sky samples keep whatever the texture held: no reader looks at them.
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            },
        })
    });
    encoder.begin_render(&wgpu::RenderPassDescriptor {
        label: Some("gbuffer"),
        color_attachments: &attachments,
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth,
            // The G-buffer tests against pre-Z's depth and never writes it: attached read-only.
            depth_ops: None,
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}
