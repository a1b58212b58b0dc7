//! Writes CPU-made depth values into a (multisampled) depth texture, sample by sample, so GPU
//! culling tests can run on exactly the depth buffer the CPU reference sees.

use renderer::GpuContext;
use renderer::shader::ShaderProgram;
use wgpu::util::DeviceExt as _;

/// Writes arbitrary per-sample depths (from a storage buffer) into a multisampled depth target.
#[shader_dsl::shader]
pub mod depth_fill {
    pub struct FillParams {
        pub width: u32,
        pub samples: u32,
    }

    pub struct VsOut {
        #[builtin(position)]
        pub position: Vec4,
    }

    pub struct FsOut {
        #[builtin(frag_depth)]
        pub depth: f32,
    }

    #[uniform(group = 0, binding = 0)]
    static FILL: FillParams;
    #[storage(group = 0, binding = 1)]
    static DEPTHS: [f32];

    #[vertex]
    pub fn vs(#[builtin(vertex_index)] vi: u32) -> VsOut {
        let uv = Vec2::new(((vi << 1u32) & 2u32) as f32, (vi & 2u32) as f32);
        VsOut {
            position: Vec4::new(uv.x * 2.0 - 1.0, uv.y * 2.0 - 1.0, 0.0, 1.0),
        }
    }

    #[fragment]
    pub fn fs(#[builtin(position)] position: Vec4, #[builtin(sample_index)] sample: u32) -> FsOut {
        let x = position.x as u32;
        let y = position.y as u32;
        FsOut {
            depth: DEPTHS[(y * FILL.width + x) * FILL.samples + sample],
        }
    }
}

/// A `samples`× multisampled `Depth32Float` texture holding `depths[(y * w + x) * samples + s]`.
pub fn write_msaa_depth(
    gpu: &GpuContext,
    w: u32,
    h: u32,
    samples: u32,
    depths: &[f32],
) -> wgpu::Texture {
    let device = gpu.device();
    let p = ShaderProgram::new(
        gpu.device(),
        gpu.capabilities(),
        depth_fill::variant(depth_fill::VariantKey::ALL[0]),
    )
    .expect("the depth fill shader runs everywhere");
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("fill params"),
        contents: bytemuck::bytes_of(&depth_fill::FillParams::new(w, samples)),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let values = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("fill depths"),
        contents: bytemuck::cast_slice(depths),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &p.bind_group_layouts[0],
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: params.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: values.as_entire_binding(),
            },
        ],
    });
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("depth fill"),
        layout: Some(&p.pipeline_layout),
        vertex: wgpu::VertexState {
            module: &p.module,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format: wgpu::TextureFormat::Depth32Float,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Always),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: wgpu::MultisampleState {
            count: samples,
            ..Default::default()
        },
        fragment: Some(wgpu::FragmentState {
            module: &p.module,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &[],
        }),
        multiview_mask: None,
        cache: None,
    });
    let depth = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("msaa depth"),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: samples,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Depth32Float,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    let view = depth.create_view(&Default::default());
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("depth fill"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.draw(0..3, 0..1);
    }
    gpu.queue().submit([encoder.finish()]);
    depth
}
