//! GPU plumbing for the forward-shading tests: textures, buffers, the draw calls of
//! `shaders_gen::forward`'s modules and float readback.

use renderer::GpuContext;
use renderer::shader::ShaderProgram;
use shaders_gen::forward::{forward, heatmap, prez, tonemap};
use wgpu::util::DeviceExt as _;

/// The binary16 bits of `x` (normal numbers and zero; mantissa truncated, exact for the values
/// the tests use: 0, 0.5, 1).
pub fn f16_bits(x: f32) -> u16 {
    if x == 0.0 {
        return 0;
    }
    let bits = x.to_bits();
    let sign = ((bits >> 16) & 0x8000) as u16;
    let exponent = ((bits >> 23) & 0xff) as i32 - 127 + 15;
    assert!((1..31).contains(&exponent), "{x} is not a normal f16");
    let mantissa = ((bits >> 13) & 0x3ff) as u16;
    sign | ((exponent as u16) << 10) | mantissa
}

pub fn program(gpu: &GpuContext, variant: &'static codegen::rt::Variant) -> ShaderProgram {
    ShaderProgram::new(&gpu.device, gpu.capabilities(), variant).expect("supported variant")
}

pub fn buffer(gpu: &GpuContext, bytes: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
    gpu.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: bytes,
            usage,
        })
}

/// A storage buffer of `items`, at least 16 bytes (an empty binding is invalid).
pub fn storage<T: bytemuck::Pod>(gpu: &GpuContext, items: &[T]) -> wgpu::Buffer {
    let mut bytes = bytemuck::cast_slice::<T, u8>(items).to_vec();
    bytes.resize(bytes.len().max(16), 0);
    buffer(gpu, &bytes, wgpu::BufferUsages::STORAGE)
}

pub fn uniform<T: bytemuck::Pod>(gpu: &GpuContext, value: &T) -> wgpu::Buffer {
    buffer(gpu, bytemuck::bytes_of(value), wgpu::BufferUsages::UNIFORM)
}

pub fn texture(
    gpu: &GpuContext,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// A texture filled with `data` (tightly packed rows).
pub fn texture_with(
    gpu: &GpuContext,
    size: (u32, u32),
    format: wgpu::TextureFormat,
    data: &[u8],
) -> wgpu::Texture {
    gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: None,
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        data,
    )
}

/// A 1×1 `Rgba16Float` texture holding `rgba` (exact for 0, 0.5 and 1).
pub fn texel(gpu: &GpuContext, rgba: [f32; 4]) -> wgpu::Texture {
    let halves = rgba.map(f16_bits);
    texture_with(
        gpu,
        (1, 1),
        wgpu::TextureFormat::Rgba16Float,
        bytemuck::cast_slice(&halves),
    )
}

/// Reads a whole texture with `texel_bytes` bytes per texel into tightly packed rows.
pub fn read_texture(gpu: &GpuContext, texture: &wgpu::Texture, texel_bytes: u32) -> Vec<u8> {
    let (width, height) = (texture.width(), texture.height());
    let row = width * texel_bytes;
    let padded = row.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let staging = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: u64::from(padded * height),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &staging,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(height),
            },
        },
        texture.size(),
    );
    gpu.queue.submit([encoder.finish()]);
    let slice = staging.slice(..);
    slice.map_async(wgpu::MapMode::Read, |r| r.expect("map"));
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("poll");
    let data = slice.get_mapped_range().expect("mapped");
    data.chunks_exact(padded as usize)
        .flat_map(|r| &r[..row as usize])
        .copied()
        .collect()
}

fn bind_group(
    gpu: &GpuContext,
    program: &ShaderProgram,
    group: usize,
    resources: Vec<(u32, wgpu::BindingResource<'_>)>,
) -> wgpu::BindGroup {
    let entries: Vec<_> = resources
        .into_iter()
        .map(|(binding, resource)| wgpu::BindGroupEntry { binding, resource })
        .collect();
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &program.bind_group_layouts[group],
        entries: &entries,
    })
}

/// Everything one forward draw reads.
pub struct ForwardInputs<'a> {
    pub size: u32,
    pub camera: forward::Camera,
    pub lighting: forward::Lighting,
    pub lights: &'a [forward::GpuLight],
    pub directional: &'a [forward::GpuLight],
    pub grid: &'a [glam::UVec2],
    pub indices: &'a [u32],
    pub draw: forward::Draw,
    pub material: forward::Material,
    /// Interleaved vertices: position, normal, uv, tangent (12 floats).
    pub vertices: &'a [[f32; 12]],
}

/// Draws `inputs.vertices` (a triangle list) with the forward variant `key` into an
/// `Rgba32Float` target cleared to zero, and returns its texels.
pub fn draw_forward(
    gpu: &GpuContext,
    key: forward::VariantKey,
    inputs: &ForwardInputs<'_>,
) -> Vec<[f32; 4]> {
    let variant = forward::variant(key).expect("not excluded");
    let p = program(gpu, variant);
    let camera = uniform(gpu, &inputs.camera);
    // No decals: every cell's decal list is an empty entry after the light lists.
    let mut lighting = inputs.lighting;
    lighting.decal_count = 0;
    lighting.decal_section = inputs.grid.len() as u32;
    let lighting = uniform(gpu, &lighting);
    let lights = storage(gpu, inputs.lights);
    let directional = storage(gpu, inputs.directional);
    let mut grid_entries = inputs.grid.to_vec();
    grid_entries.resize(inputs.grid.len() * 2, glam::UVec2::ZERO);
    let grid = storage(gpu, &grid_entries);
    let indices = storage(gpu, inputs.indices);
    let mut group0 = vec![
        (0, camera.as_entire_binding()),
        (1, lighting.as_entire_binding()),
        (2, lights.as_entire_binding()),
        (3, directional.as_entire_binding()),
    ];
    if key.list != forward::List::List0 {
        group0.push((4, grid.as_entire_binding()));
        group0.push((5, indices.as_entire_binding()));
    }
    // No light has a shadow here (`NO_SHADOW`): a placeholder atlas and view record.
    let shadow_views = storage(gpu, &[0u8; size_of::<forward::ShadowView>()]);
    let shadow_atlas = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("placeholder shadow atlas"),
        size: wgpu::Extent3d {
            width: 1,
            height: 1,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Depth32Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    let shadow_view = shadow_atlas.create_view(&Default::default());
    let shadow_sampler = gpu.device.create_sampler(&wgpu::SamplerDescriptor {
        compare: Some(wgpu::CompareFunction::GreaterEqual),
        ..Default::default()
    });
    group0.push((6, shadow_views.as_entire_binding()));
    group0.push((7, wgpu::BindingResource::TextureView(&shadow_view)));
    group0.push((8, wgpu::BindingResource::Sampler(&shadow_sampler)));
    let decal_records = storage(gpu, &[0u8; size_of::<forward::GpuDecal>()]);
    let decal_texel = texel(gpu, [0.0; 4]).create_view(&Default::default());
    let decal_sampler = gpu.device.create_sampler(&Default::default());
    group0.push((9, decal_records.as_entire_binding()));
    for binding in 10..14 {
        group0.push((binding, wgpu::BindingResource::TextureView(&decal_texel)));
    }
    group0.push((14, wgpu::BindingResource::Sampler(&decal_sampler)));
    let g0 = bind_group(gpu, &p, 0, group0);
    let draw = uniform(gpu, &inputs.draw);
    let g1 = bind_group(gpu, &p, 1, vec![(0, draw.as_entire_binding())]);
    let material = uniform(gpu, &inputs.material);
    let white = texel(gpu, [1.0; 4]).create_view(&Default::default());
    let flat = texel(gpu, [0.5, 0.5, 1.0, 1.0]).create_view(&Default::default());
    let sampler = gpu.device.create_sampler(&Default::default());
    let g2 = bind_group(
        gpu,
        &p,
        2,
        vec![
            (0, material.as_entire_binding()),
            (1, wgpu::BindingResource::TextureView(&white)),
            (2, wgpu::BindingResource::TextureView(&flat)),
            (3, wgpu::BindingResource::TextureView(&white)),
            (4, wgpu::BindingResource::TextureView(&white)),
            (5, wgpu::BindingResource::TextureView(&white)),
            (6, wgpu::BindingResource::Sampler(&sampler)),
        ],
    );
    let vertices = buffer(
        gpu,
        bytemuck::cast_slice(inputs.vertices),
        wgpu::BufferUsages::VERTEX,
    );
    let format = wgpu::TextureFormat::Rgba32Float;
    let pipeline = gpu
        .device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("forward"),
            layout: Some(&p.pipeline_layout),
            vertex: wgpu::VertexState {
                module: &p.module,
                entry_point: Some("vs_forward"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: 48,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![
                        0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4
                    ],
                })],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &p.module,
                entry_point: Some("fs_forward"),
                compilation_options: Default::default(),
                targets: &[Some(format.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
    let size = (inputs.size, inputs.size);
    let target = texture(
        gpu,
        size,
        format,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    );
    let view = target.create_view(&Default::default());
    let attachments = cleared(&view);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_render_pass(&color_pass(&attachments));
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &g0, &[]);
        pass.set_bind_group(1, &g1, &[]);
        pass.set_bind_group(2, &g2, &[]);
        pass.set_vertex_buffer(0, vertices.slice(..));
        pass.draw(0..inputs.vertices.len() as u32, 0..1);
    }
    gpu.queue.submit([encoder.finish()]);
    bytemuck::pod_collect_to_vec(&read_texture(gpu, &target, 16))
}

/// A colour attachment cleared to transparent black and stored.
fn cleared(view: &wgpu::TextureView) -> [Option<wgpu::RenderPassColorAttachment<'_>>; 1] {
    [Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
            store: wgpu::StoreOp::Store,
        },
    })]
}

fn color_pass<'a>(
    attachments: &'a [Option<wgpu::RenderPassColorAttachment<'a>>],
) -> wgpu::RenderPassDescriptor<'a> {
    wgpu::RenderPassDescriptor {
        label: None,
        color_attachments: attachments,
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    }
}

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
        .device
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
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_render_pass(&color_pass(&attachments));
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &g0, &[]);
        pass.draw(0..3, 0..1);
    }
    gpu.queue.submit([encoder.finish()]);
    read_texture(gpu, &target, format.block_copy_size(None).expect("color"))
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
    let params = uniform(gpu, &tonemap::TonemapParams::new(exposure, 1.0));
    let input = texture_with(
        gpu,
        size,
        wgpu::TextureFormat::Rgba32Float,
        bytemuck::cast_slice(hdr),
    );
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
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
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
    gpu.queue.submit([encoder.finish()]);
    let mut group0 = vec![
        (0, params_buffer.as_entire_binding()),
        (1, grid.as_entire_binding()),
        (2, indices.as_entire_binding()),
    ];
    if key.list == heatmap::List::List2 {
        group0.push((3, wgpu::BindingResource::TextureView(&depth_view)));
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
    let draw = uniform(gpu, draw);
    let g0 = bind_group(gpu, &p, 0, vec![(0, camera.as_entire_binding())]);
    let g1 = bind_group(gpu, &p, 1, vec![(0, draw.as_entire_binding())]);
    let vertex_buffer = buffer(
        gpu,
        bytemuck::cast_slice(vertices),
        wgpu::BufferUsages::VERTEX,
    );
    let format = wgpu::TextureFormat::Depth32Float;
    let pipeline = gpu
        .device
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
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
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
    gpu.queue.submit([encoder.finish()]);
    bytemuck::pod_collect_to_vec(&read_texture(gpu, &target, 4))
}
