//! A scene prepared for drawing: its GPU buffers and images, one uniform + bind group per draw,
//! and one material bind group per material (with 1×1 defaults for absent textures).

use std::sync::Arc;

use glam::{Vec3, Vec4};
use shaders_gen::forward::forward;
use wgpu::util::DeviceExt as _;

use crate::scene::{AlphaMode, GpuScene, Material, Scene, TextureRef};
use crate::shader::ShaderProgram;

/// One primitive of one instance.
#[derive(Debug)]
pub struct DrawItem {
    pub mesh: usize,
    pub primitive: usize,
    pub material: usize,
    pub bind_group: wgpu::BindGroup,
    /// Distance from the camera's eye, for sorting blended draws (set each frame).
    pub center: Vec3,
}

/// What a material draws with.
#[derive(Debug)]
pub struct PreparedMaterial {
    pub bind_group: wgpu::BindGroup,
    /// Group 2 of the masked pre-Z program, for alpha-masked materials.
    pub prez_mask_group: Option<wgpu::BindGroup>,
    pub alpha_mode: AlphaMode,
    pub double_sided: bool,
}

/// A scene on the GPU, ready for the passes.
#[derive(Debug)]
pub struct PreparedScene {
    pub gpu: GpuScene,
    pub draws: Vec<DrawItem>,
    pub materials: Vec<PreparedMaterial>,
}

impl PreparedScene {
    /// Uploads `scene` and builds bind groups against the forward program's layouts (groups 1
    /// and 2), which the pre-Z program shares for group 1.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        forward: &ShaderProgram,
        prez_mask: &ShaderProgram,
    ) -> Arc<Self> {
        let gpu = GpuScene::upload(device, queue, scene);
        let defaults = Defaults::new(device, queue);
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("material sampler"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let mut materials: Vec<PreparedMaterial> = scene
            .materials
            .iter()
            .map(|m| prepare_material(device, [forward, prez_mask], &gpu, &defaults, &sampler, m))
            .collect();
        // Primitives without a material use the glTF default material.
        let default_material = materials.len();
        materials.push(prepare_material(
            device,
            [forward, prez_mask],
            &gpu,
            &defaults,
            &sampler,
            &Material::gltf_default(),
        ));
        let mut draws = Vec::new();
        for instance in &scene.instances {
            for (p, primitive) in scene.meshes[instance.mesh].primitives.iter().enumerate() {
                let material = primitive.material.unwrap_or(default_material);
                let world = instance.world_from_mesh;
                let draw = forward::Draw::new(world, world.inverse().transpose(), material as u32);
                let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("draw"),
                    contents: bytemuck::bytes_of(&draw),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
                let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("draw"),
                    layout: &forward.bind_group_layouts[1],
                    entries: &[wgpu::BindGroupEntry {
                        binding: 0,
                        resource: buffer.as_entire_binding(),
                    }],
                });
                draws.push(DrawItem {
                    mesh: instance.mesh,
                    primitive: p,
                    material,
                    bind_group,
                    center: primitive.bounds.transformed(world).center(),
                });
            }
        }
        Arc::new(Self {
            gpu,
            draws,
            materials,
        })
    }
}

/// 1×1 textures standing in for absent material textures.
struct Defaults {
    white: wgpu::TextureView,
    flat_normal: wgpu::TextureView,
    black: wgpu::TextureView,
}

impl Defaults {
    fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
        let texel = |rgba: [u8; 4], format| {
            device
                .create_texture_with_data(
                    queue,
                    &wgpu::TextureDescriptor {
                        label: Some("default texel"),
                        size: wgpu::Extent3d {
                            width: 1,
                            height: 1,
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
                    &rgba,
                )
                .create_view(&Default::default())
        };
        Self {
            white: texel([255; 4], wgpu::TextureFormat::Rgba8UnormSrgb),
            flat_normal: texel([128, 128, 255, 255], wgpu::TextureFormat::Rgba8Unorm),
            black: texel([0, 0, 0, 255], wgpu::TextureFormat::Rgba8UnormSrgb),
        }
    }
}

fn prepare_material(
    device: &wgpu::Device,
    [forward, prez_mask]: [&ShaderProgram; 2],
    gpu: &GpuScene,
    defaults: &Defaults,
    sampler: &wgpu::Sampler,
    m: &Material,
) -> PreparedMaterial {
    let cutoff = match m.alpha_mode {
        AlphaMode::Mask { cutoff } => cutoff,
        _ => 0.0,
    };
    let uniform = forward::Material::new(
        m.base_color,
        m.emissive,
        m.metallic,
        m.roughness,
        m.normal_scale,
        m.occlusion_strength,
        cutoff,
    );
    let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("material"),
        contents: bytemuck::bytes_of(&uniform),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let view =
        |t: Option<TextureRef>, colour: bool, fallback: &wgpu::TextureView| -> wgpu::TextureView {
            t.map_or_else(|| fallback.clone(), |t| gpu.view(t, colour).clone())
        };
    let views = [
        view(m.base_color_texture, true, &defaults.white),
        view(m.normal_texture, false, &defaults.flat_normal),
        view(m.metallic_roughness_texture, false, &defaults.white),
        view(m.occlusion_texture, false, &defaults.white),
        view(
            m.emissive_texture,
            true,
            if m.emissive == Vec3::ZERO {
                &defaults.black
            } else {
                &defaults.white
            },
        ),
    ];
    let mut entries = vec![wgpu::BindGroupEntry {
        binding: 0,
        resource: buffer.as_entire_binding(),
    }];
    entries.extend(views.iter().enumerate().map(|(i, v)| wgpu::BindGroupEntry {
        binding: i as u32 + 1,
        resource: wgpu::BindingResource::TextureView(v),
    }));
    entries.push(wgpu::BindGroupEntry {
        binding: 6,
        resource: wgpu::BindingResource::Sampler(sampler),
    });
    let prez_mask_group = matches!(m.alpha_mode, AlphaMode::Mask { .. }).then(|| {
        let mask = shaders_gen::forward::prez::MaskMaterial::new(m.base_color, cutoff);
        let mask_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("mask material"),
            contents: bytemuck::bytes_of(&mask),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("pre-z mask material"),
            layout: &prez_mask.bind_group_layouts[2],
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: mask_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&views[0]),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::Sampler(sampler),
                },
            ],
        })
    });
    PreparedMaterial {
        prez_mask_group,
        bind_group: device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("material"),
            layout: &forward.bind_group_layouts[2],
            entries: &entries,
        }),
        alpha_mode: m.alpha_mode,
        double_sided: m.double_sided,
    }
}

impl Material {
    /// The glTF 2.0 default material (white, metallic 1, roughness 1), for primitives without one.
    pub fn gltf_default() -> Self {
        Self {
            name: "default".into(),
            base_color: Vec4::ONE,
            base_color_texture: None,
            metallic: 1.0,
            roughness: 1.0,
            metallic_roughness_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
            occlusion_texture: None,
            occlusion_strength: 1.0,
            emissive: Vec3::ZERO,
            emissive_texture: None,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
        }
    }
}
