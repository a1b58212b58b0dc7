//! The other programs of `shaders_gen::forward`'s modules: the full-screen tonemap and
//! heatmap passes and the depth pre-pass, each drawn into a new target and read back.

use renderer::GpuContext;
use renderer::shader::ShaderProgram;
use shaders_gen::forward::{heatmap, prez, tonemap, tonemap_compute};

use super::resources::{
    bind_group, buffer, cleared, color_pass, program, read_texture, storage, texture, texture_with,
    uniform,
};

/// Runs a full-screen (3-vertex) pass of `p` into a new `format` target of `size`, with
/// `group0` bound, and returns the target's bytes (`texel_bytes` per texel).
fn fullscreen(
    gpu: &GpuContext,
    p: &ShaderProgram,
    (vs, fs): (&str, &str),
    group0: Vec<(u32, wgpu::BindingResource<'_>)>,
    size: (u32, u32),
    format: wgpu::TextureFormat,
) -> Vec<u8> {
    let g0 = bind_group(gpu, p, 0, group0);
    let pipeline = gpu
        .device()
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(fs),
            layout: Some(&p.pipeline_layout),
            vertex: wgpu::VertexState {
                module: &p.module,
                entry_point: Some(vs),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &p.module,
                entry_point: Some(fs),
                compilation_options: Default::default(),
                targets: &[Some(format.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
    let target = texture(
        gpu,
        size,
        format,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    );
    let view = target.create_view(&Default::default());
    let attachments = cleared(&view);
    let mut encoder = gpu.device().create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_render_pass(&color_pass(&attachments));
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &g0, &[]);
        pass.draw(0..3, 0..1);
    }
    gpu.queue().submit([encoder.finish()]);
    read_texture(gpu, &target, format.block_copy_size(None).expect("color"))
}

/// What both tonemaps read: their parameters (`exposure`, the source at the target's scale) and
/// `hdr` as an `Rgba32Float` texture of `size`.
fn tonemap_inputs(
    gpu: &GpuContext,
    exposure: f32,
    size: (u32, u32),
    hdr: &[[f32; 4]],
) -> (wgpu::Buffer, wgpu::Texture) {
    let params = uniform(gpu, &tonemap::TonemapParams::new(exposure, 1.0));
    let input = texture_with(
        gpu,
        size,
        wgpu::TextureFormat::Rgba32Float,
        bytemuck::cast_slice(hdr),
    );
    (params, input)
}

/// Tonemaps an `Rgba32Float` image of `size` into `Rgba8UnormSrgb` bytes.
pub fn draw_tonemap(
    gpu: &GpuContext,
    key: tonemap::VariantKey,
    exposure: f32,
    size: (u32, u32),
    hdr: &[[f32; 4]],
) -> Vec<u8> {
    let p = program(gpu, tonemap::variant(key));
    let (params, input) = tonemap_inputs(gpu, exposure, size, hdr);
    let view = input.create_view(&Default::default());
    fullscreen(
        gpu,
        &p,
        ("vs_fullscreen", "fs_tonemap"),
        vec![
            (0, params.as_entire_binding()),
            (1, wgpu::BindingResource::TextureView(&view)),
        ],
        size,
        wgpu::TextureFormat::Rgba8UnormSrgb,
    )
}

/// Tonemaps an `Rgba32Float` image of `size` with the compute kernel into `Rgba8Unorm` bytes
/// (sRGB-encoded by the kernel where `key.srgb`).
pub fn dispatch_tonemap(
    gpu: &GpuContext,
    key: tonemap_compute::VariantKey,
    exposure: f32,
    size: (u32, u32),
    hdr: &[[f32; 4]],
) -> Vec<u8> {
    let p = program(gpu, tonemap_compute::variant(key));
    let (params, input) = tonemap_inputs(gpu, exposure, size, hdr);
    let output = texture(
        gpu,
        size,
        wgpu::TextureFormat::Rgba8Unorm,
        wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
    );
    let (input_view, output_view) = (
        input.create_view(&Default::default()),
        output.create_view(&Default::default()),
    );
    let group = bind_group(
        gpu,
        &p,
        0,
        vec![
            (0, params.as_entire_binding()),
            (1, wgpu::BindingResource::TextureView(&input_view)),
            (2, wgpu::BindingResource::TextureView(&output_view)),
        ],
    );
    let pipeline = p
        .compute_pipeline(gpu.device(), "cs_tonemap")
        .expect("cs_tonemap");
    let mut encoder = gpu.device().create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups(size.0.div_ceil(8), size.1.div_ceil(8), 1);
    }
    gpu.queue().submit([encoder.finish()]);
    read_texture(gpu, &output, 4)
}

/// Draws the heatmap into an `Rgba8Unorm` target; for the clustered variant the depth buffer
/// is a `Depth32Float` texture cleared to `depth`.
pub fn draw_heatmap(
    gpu: &GpuContext,
    key: heatmap::VariantKey,
    params: &heatmap::HeatmapParams,
    grid: &[glam::UVec2],
    depth: f32,
) -> Vec<u8> {
    let p = program(gpu, heatmap::variant(key).expect("not excluded"));
    let params_buffer = uniform(gpu, params);
    let grid = storage(gpu, grid);
    let indices = storage(gpu, &[0u32; 4]);
    let size = (params.screen.x, params.screen.y);
    let depth_texture = texture(
        gpu,
        size,
        wgpu::TextureFormat::Depth32Float,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
    );
    let depth_view = depth_texture.create_view(&Default::default());
    let mut encoder = gpu.device().create_command_encoder(&Default::default());
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("clear depth"),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &depth_view,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(depth),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    gpu.queue().submit([encoder.finish()]);
    // The light records are bound (the `light_lists` contract) but not read.
    let no_lights = storage(gpu, &[heatmap::GpuLight::default()]);
    let mut group0 = vec![
        (0, params_buffer.as_entire_binding()),
        (1, no_lights.as_entire_binding()),
        (2, no_lights.as_entire_binding()),
        (3, grid.as_entire_binding()),
        (4, indices.as_entire_binding()),
    ];
    if key.list == heatmap::List::List2 {
        group0.push((5, wgpu::BindingResource::TextureView(&depth_view)));
    }
    fullscreen(
        gpu,
        &p,
        ("vs_fullscreen", "fs_heatmap"),
        group0,
        size,
        wgpu::TextureFormat::Rgba8Unorm,
    )
}

/// Runs the depth pre-pass over `vertices` (position, uv: 5 floats) into a `Depth32Float`
/// target of `size`² cleared to 1 (compare `Less`), and returns the depths.
pub fn draw_prez(
    gpu: &GpuContext,
    size: u32,
    camera: &prez::Camera,
    draw: &prez::Draw,
    vertices: &[[f32; 5]],
) -> Vec<f32> {
    let p = program(gpu, prez::variant(prez::VariantKey::ALL[0]));
    let camera = uniform(gpu, camera);
    // The draw records (`DRAWS`): one, read as instance 0.
    let draw = storage(gpu, std::slice::from_ref(draw));
    let g0 = bind_group(gpu, &p, 0, vec![(0, camera.as_entire_binding())]);
    let g1 = bind_group(gpu, &p, 1, vec![(0, draw.as_entire_binding())]);
    let vertex_buffer = buffer(
        gpu,
        bytemuck::cast_slice(vertices),
        wgpu::BufferUsages::VERTEX,
    );
    let format = wgpu::TextureFormat::Depth32Float;
    let pipeline = gpu
        .device()
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("prez"),
            layout: Some(&p.pipeline_layout),
            vertex: wgpu::VertexState {
                module: &p.module,
                entry_point: Some("vs_prez"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: 20,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x2],
                })],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        });
    let target = texture(
        gpu,
        (size, size),
        format,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    );
    let view = target.create_view(&Default::default());
    let mut encoder = gpu.device().create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("prez"),
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
        pass.set_bind_group(0, &g0, &[]);
        pass.set_bind_group(1, &g1, &[]);
        pass.set_vertex_buffer(0, vertex_buffer.slice(..));
        pass.draw(0..vertices.len() as u32, 0..1);
    }
    gpu.queue().submit([encoder.finish()]);
    bytemuck::pod_collect_to_vec(&read_texture(gpu, &target, 4))
}
