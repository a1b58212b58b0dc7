//! GPU plumbing for the forward-shading tests: textures, buffers, the draw calls of
//! `shaders_gen::forward`'s modules and float readback.
//!
//! `resources` has the textures, buffers, bind groups, colour attachments and readback the
//! draws share; `passes` the full-screen passes and the depth pre-pass; the forward draw is
//! here.

mod passes;
mod resources;

pub use passes::{dispatch_tonemap, draw_heatmap, draw_prez, draw_tonemap};

use renderer::GpuContext;
use shaders_gen::forward::forward;

use resources::{
    bind_group, buffer, cleared, color_pass, program, read_texture, storage, texel, texture,
    uniform,
};

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
    pub material: forward::GpuMaterial,
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
        (1, lights.as_entire_binding()),
        (2, directional.as_entire_binding()),
        (5, lighting.as_entire_binding()),
    ];
    if key.list != forward::List::List0 {
        group0.push((3, grid.as_entire_binding()));
        group0.push((4, indices.as_entire_binding()));
    }
    // No light has a shadow here (`NO_SHADOW`): a placeholder atlas and view record.
    let shadow_views = storage(gpu, &[0u8; size_of::<forward::ShadowView>()]);
    let shadow_atlas = gpu.device().create_texture(&wgpu::TextureDescriptor {
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
    let shadow_sampler = gpu.device().create_sampler(&wgpu::SamplerDescriptor {
        compare: Some(wgpu::CompareFunction::GreaterEqual),
        ..Default::default()
    });
    group0.push((6, shadow_views.as_entire_binding()));
    group0.push((7, wgpu::BindingResource::TextureView(&shadow_view)));
    group0.push((8, wgpu::BindingResource::Sampler(&shadow_sampler)));
    let decal_records = storage(gpu, &[0u8; size_of::<forward::GpuDecal>()]);
    let decal_texel = texel(gpu, [0.0; 4]).create_view(&Default::default());
    let decal_sampler = gpu.device().create_sampler(&Default::default());
    group0.push((9, decal_records.as_entire_binding()));
    for binding in 10..14 {
        group0.push((binding, wgpu::BindingResource::TextureView(&decal_texel)));
    }
    group0.push((14, wgpu::BindingResource::Sampler(&decal_sampler)));
    let g0 = bind_group(gpu, &p, 0, group0);
    // The draw records (`DRAWS`): one, read as instance 0.
    let draw = storage(gpu, std::slice::from_ref(&inputs.draw));
    let g1 = bind_group(gpu, &p, 1, vec![(0, draw.as_entire_binding())]);
    // The material (`MATERIALS`: one record, without textures) and an empty material atlas.
    let material = storage(gpu, std::slice::from_ref(&inputs.material));
    let no_images: &[renderer::scene::Image] = &[];
    let atlas = renderer::scene::MaterialAtlas::new(gpu.device(), gpu.queue(), no_images, &[])
        .expect("an empty atlas");
    let g2 = forward::Group2 {
        material_table: shaders_gen::shared::material_table::Group2 {
            materials: material.as_entire_buffer_binding(),
        },
        material_atlas: atlas.bindings(),
    }
    .bind_group(gpu.device(), p.layout(2), p.variant, "materials")
    .expect("group 2 binds");
    // TEXCOORD_1 and a white COLOR_0, one value for the whole draw (instance step).
    let uv1_color: [f32; 6] = [0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    let constant_streams = buffer(
        gpu,
        bytemuck::cast_slice(&uv1_color),
        wgpu::BufferUsages::VERTEX,
    );
    let vertices = buffer(
        gpu,
        bytemuck::cast_slice(inputs.vertices),
        wgpu::BufferUsages::VERTEX,
    );
    let format = wgpu::TextureFormat::Rgba32Float;
    let pipeline = gpu
        .device()
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("forward"),
            layout: Some(&p.pipeline_layout),
            vertex: wgpu::VertexState {
                module: &p.module,
                entry_point: Some("vs_forward"),
                compilation_options: Default::default(),
                buffers: &[
                    Some(wgpu::VertexBufferLayout {
                        array_stride: 48,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &wgpu::vertex_attr_array![
                            0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4
                        ],
                    }),
                    Some(wgpu::VertexBufferLayout {
                        array_stride: 24,
                        step_mode: wgpu::VertexStepMode::Instance,
                        attributes: &wgpu::vertex_attr_array![4 => Float32x2, 5 => Float32x4],
                    }),
                ],
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
    let mut encoder = gpu.device().create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_render_pass(&color_pass(&attachments));
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &g0, &[]);
        pass.set_bind_group(1, &g1, &[]);
        pass.set_bind_group(2, &g2, &[]);
        pass.set_vertex_buffer(0, vertices.slice(..));
        pass.set_vertex_buffer(1, constant_streams.slice(..));
        pass.draw(0..inputs.vertices.len() as u32, 0..1);
    }
    gpu.queue().submit([encoder.finish()]);
    bytemuck::pod_collect_to_vec(&read_texture(gpu, &target, 16))
}
