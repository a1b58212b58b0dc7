//! Forward shading: PBR over the frame's light list (every light, or the culled cell lists)
//! into the MSAA HDR target, resolved to a single-sample HDR texture. Opaque draws first, then
//! blended draws back to front. After the pre-pass it tests depth with `LessEqual` against the
//! pre-Z depth (both vertex stages compute the position with the same `#[invariant]` code);
//! without one (the naive path) it writes its own.

use std::sync::Arc;

use shaders_gen::forward::forward;

use super::{MeshPipeline, Pass, depth_state, draw_primitive, mesh_pipeline};
use crate::GpuContext;
use crate::frame_data::{
    DEPTH_FORMAT, FrameInputs, FrameResources, HDR_FORMAT, LightListHandles, ListGeometry,
    PreparedScene, RenderError, RendererConfig, ShadowResources,
};
use crate::graph::{BufferAccess, Handle, RenderGraph, Texture, TextureAccess, TextureDesc};
use crate::scene::AlphaMode;
use crate::shader::ShaderProgram;

/// The forward pass: its program and pipelines (`[blend][double_sided]`) and its lighting
/// uniform.
#[derive(Debug)]
pub struct ForwardPass {
    program: ShaderProgram,
    pipelines: Arc<[[wgpu::RenderPipeline; 2]; 2]>,
    lighting: wgpu::Buffer,
}

impl ForwardPass {
    pub fn new(gpu: &GpuContext, config: &RendererConfig) -> Result<Self, RenderError> {
        let list = match config.path {
            crate::frame_data::RenderPath::Naive | crate::frame_data::RenderPath::NaivePrez => {
                forward::List::List0
            }
            crate::frame_data::RenderPath::Tiled | crate::frame_data::RenderPath::Depth25 => {
                forward::List::List1
            }
            crate::frame_data::RenderPath::Clustered => forward::List::List2,
        };
        let key = |blend| forward::VariantKey {
            list,
            blend,
            scalarize: config.scalarize && config.path.is_culled(),
        };
        let caps = gpu.capabilities();
        let opaque = ShaderProgram::new(&gpu.device, caps, forward::variant(key(false))?)?;
        let blended = ShaderProgram::new(&gpu.device, caps, forward::variant(key(true))?)?;
        let prepass = config.path.has_prepass();
        let make = |program: &ShaderProgram, blend: bool| {
            [false, true].map(|d| pipeline(&gpu.device, program, config.msaa, prepass, blend, d))
        };
        Ok(Self {
            pipelines: Arc::new([make(&opaque, false), make(&blended, true)]),
            program: opaque,
            lighting: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("lighting"),
                size: size_of::<forward::Lighting>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        })
    }

    /// Writes the frame's light counts and the geometry of its light lists.
    fn write_lighting(&self, frame: &FrameInputs, lists: Option<&LightListHandles>) {
        let c = &frame.config;
        let g = ListGeometry::new(lists.map(|l| l.method), c, &frame.camera);
        let lighting = forward::Lighting::new(
            c.ambient,
            frame.lights.punctual.len() as u32,
            g.tiles,
            g.tile,
            g.slices,
            g.blend_cell_offset,
            g.near,
            g.far,
            frame.lights.directional.len() as u32,
            frame.decals.count(),
            g.decal_section,
        );
        frame
            .gpu
            .queue
            .write_buffer(&self.lighting, 0, bytemuck::bytes_of(&lighting));
    }
}

fn pipeline(
    device: &wgpu::Device,
    program: &ShaderProgram,
    msaa: u32,
    prepass: bool,
    blend: bool,
    double_sided: bool,
) -> wgpu::RenderPipeline {
    let target = wgpu::ColorTargetState {
        format: HDR_FORMAT,
        blend: blend.then_some(wgpu::BlendState::ALPHA_BLENDING),
        write_mask: wgpu::ColorWrites::ALL,
    };
    let streams = [
        wgpu::VertexFormat::Float32x3,
        wgpu::VertexFormat::Float32x3,
        wgpu::VertexFormat::Float32x2,
        wgpu::VertexFormat::Float32x4,
    ];
    mesh_pipeline(
        device,
        program,
        &MeshPipeline {
            label: if blend { "forward blend" } else { "forward" },
            vertex_entry: "vs_forward",
            streams: &streams,
            double_sided,
            // With a pre-pass, opaque surfaces are in the depth buffer already and blended ones
            // test against it; without one, opaque draws write depth themselves.
            depth: if prepass || blend {
                depth_state(false, wgpu::CompareFunction::LessEqual)
            } else {
                depth_state(true, wgpu::CompareFunction::Less)
            },
            msaa,
            fragment: Some(("fs_forward", &[Some(target)])),
        },
    )
}

/// Draw order: opaque and masked first (any order), then blended back to front from `eye`.
fn draw_order(scene: &PreparedScene, eye: glam::Vec3) -> Vec<usize> {
    let blend = |i: usize| scene.materials[scene.draws[i].material].alpha_mode == AlphaMode::Blend;
    let mut order: Vec<usize> = (0..scene.draws.len()).collect();
    order.sort_by(|&a, &b| {
        blend(a).cmp(&blend(b)).then_with(|| {
            if blend(a) {
                let d = |i: usize| scene.draws[i].center.distance_squared(eye);
                d(b).total_cmp(&d(a))
            } else {
                std::cmp::Ordering::Equal
            }
        })
    });
    order
}

/// The colour and depth targets of the pass.
struct Targets {
    resolved: Handle<Texture>,
    multisampled: Option<Handle<Texture>>,
    depth: Handle<Texture>,
    /// Whether `depth` holds the pre-pass's depth (load it) or is the pass's own (clear it).
    prepass: bool,
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
        let lists = resources.light_lists.clone();
        if frame.config.path.is_culled() && lists.is_none() {
            return Err(RenderError::MissingInput {
                pass: "forward",
                input: "light lists",
            });
        }
        self.write_lighting(frame, lists.as_ref());
        let desc = TextureDesc::new_2d(c.width, c.height, HDR_FORMAT);
        let mut hdr = graph.create_texture("hdr", desc);
        let mut hdr_msaa =
            (c.msaa > 1).then(|| graph.create_texture("hdr msaa", desc.with_samples(c.msaa)));
        let mut own_depth = resources.depth.is_none().then(|| {
            let desc = TextureDesc::new_2d(c.width, c.height, DEPTH_FORMAT).with_samples(c.msaa);
            graph.create_texture("depth", desc)
        });
        let targets = Targets {
            resolved: hdr,
            multisampled: hdr_msaa,
            depth: resources
                .depth
                .or(own_depth)
                .ok_or(RenderError::MissingInput {
                    pass: "forward",
                    input: "depth buffer",
                })?,
            prepass: resources.depth.is_some(),
        };
        let mut pass = graph.add_pass(self.name());
        match (resources.depth, own_depth.as_mut()) {
            (Some(d), _) => pass.read_texture(d, TextureAccess::DepthRead),
            (None, Some(d)) => pass.write_texture(d, TextureAccess::DepthWrite),
            (None, None) => &mut pass,
        };
        pass.write_texture(&mut hdr, TextureAccess::ColorAttachment);
        if let Some(h) = hdr_msaa.as_mut() {
            pass.write_texture(h, TextureAccess::ColorAttachment);
        }
        if let Some(l) = &lists {
            pass.read_buffer(l.grid, BufferAccess::StorageRead)
                .read_buffer(l.indices, BufferAccess::StorageRead);
        }
        let shadows = resources.shadows.clone().ok_or(RenderError::MissingInput {
            pass: "forward",
            input: "shadow atlas",
        })?;
        pass.read_texture(shadows.atlas, TextureAccess::Sampled);
        let record = self.recorder(frame, targets, lists, shadows);
        pass.execute(record);
        resources.hdr = Some(hdr);
        resources.hdr_multisampled = hdr_msaa;
        if resources.depth.is_none() {
            resources.depth = own_depth;
        }
        Ok(())
    }
}

impl ForwardPass {
    /// The recording function of one frame.
    fn recorder(
        &self,
        frame: &FrameInputs,
        targets: Targets,
        lists: Option<LightListHandles>,
        shadows: ShadowResources,
    ) -> impl FnOnce(&mut crate::graph::PassContext<'_>) + 'static {
        let layout = self.program.bind_group_layouts[0].clone();
        let pipelines = Arc::clone(&self.pipelines);
        let scene = Arc::clone(&frame.scene);
        let camera = frame.camera_uniform.buffer.clone();
        let lighting = self.lighting.clone();
        let lights = Arc::clone(&frame.lights);
        let decals = Arc::clone(&frame.decals);
        let eye = frame.camera.eye;
        let sky = sky_color(frame.config.sky);
        move |ctx| {
            let mut frame_resources = vec![
                camera.as_entire_binding(),
                lighting.as_entire_binding(),
                lights.punctual_buffer.as_entire_binding(),
                lights.directional_buffer.as_entire_binding(),
            ];
            if let Some(l) = &lists {
                frame_resources.push(ctx.buffer(l.grid).as_entire_binding());
                frame_resources.push(ctx.buffer(l.indices).as_entire_binding());
            }
            let mut entries = super::entries(&frame_resources);
            entries.extend(shadows.entries());
            entries.extend(decals.entries());
            let frame_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("forward frame"),
                layout: &layout,
                entries: &entries,
            });
            let depth_view = ctx.texture(targets.depth).create_view(&Default::default());
            let resolved_view = ctx
                .texture(targets.resolved)
                .create_view(&Default::default());
            let msaa_view = targets
                .multisampled
                .map(|h| ctx.texture(h).create_view(&Default::default()));
            let mut pass = ctx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("forward"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: msaa_view.as_ref().unwrap_or(&resolved_view),
                    depth_slice: None,
                    resolve_target: msaa_view.as_ref().map(|_| &resolved_view),
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(sky),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: if targets.prepass {
                            wgpu::LoadOp::Load
                        } else {
                            wgpu::LoadOp::Clear(1.0)
                        },
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &frame_group, &[]);
            for i in draw_order(&scene, eye) {
                let draw = &scene.draws[i];
                let material = &scene.materials[draw.material];
                let blend = material.alpha_mode == AlphaMode::Blend;
                pass.set_pipeline(
                    &pipelines[usize::from(blend)][usize::from(material.double_sided)],
                );
                pass.set_bind_group(1, &draw.bind_group, &[]);
                pass.set_bind_group(2, &material.bind_group, &[]);
                let p = &scene.gpu.meshes[draw.mesh][draw.primitive];
                draw_primitive(
                    &mut pass,
                    p,
                    &[&p.positions, &p.normals, &p.uvs, &p.tangents],
                );
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
