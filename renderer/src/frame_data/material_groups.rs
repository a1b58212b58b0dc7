//! A material's bind groups: its uniform, its five textures (1×1 stand-ins for absent ones)
//! and their samplers as group 2 of the forward and G-buffer programs, and its alpha mask as
//! group 2 of the masked pre-Z and shadow-caster programs, built against the layouts the DSL
//! reflects.

use glam::Vec3;
use shaders_gen::forward::forward;
use shaders_gen::shared::material_uv::MaskMaterial;
use wgpu::util::DeviceExt as _;

use super::material_inputs::{Samplers, uv_map};
use crate::scene::{AlphaMode, GpuScene, Material, TextureRef};
use crate::shader::bind_group_layout_entries;

/// What a material draws with.
#[derive(Debug, Clone)]
pub struct PreparedMaterial {
    pub bind_group: wgpu::BindGroup,
    /// Group 2 of the masked pre-Z and masked shadow-caster programs, for alpha-masked
    /// materials.
    pub prez_mask_group: Option<wgpu::BindGroup>,
    pub alpha_mode: AlphaMode,
    pub double_sided: bool,
}

/// The `Material` uniform of `m` (the alpha cutoff is 0 unless the material is masked), with each
/// texture's UV set and transform.
pub fn material_uniform(m: &Material) -> forward::Material {
    let cutoff = match m.alpha_mode {
        AlphaMode::Mask { cutoff } => cutoff,
        _ => 0.0,
    };
    forward::Material::new(
        m.base_color,
        m.emissive,
        m.metallic,
        m.roughness,
        m.normal_scale,
        m.occlusion_strength,
        cutoff,
        uv_map(m.base_color_texture),
        uv_map(m.normal_texture),
        uv_map(m.metallic_roughness_texture),
        uv_map(m.occlusion_texture),
        uv_map(m.emissive_texture),
    )
}

/// 1×1 textures standing in for absent material textures.
#[derive(Debug, Clone)]
pub(super) struct Defaults {
    white: wgpu::TextureView,
    flat_normal: wgpu::TextureView,
    black: wgpu::TextureView,
}

impl Defaults {
    pub(super) fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
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

/// The bind-group layouts of the scene's draw-record and per-material groups.
#[derive(Debug, Clone)]
pub(super) struct SceneLayouts {
    pub(super) draw: wgpu::BindGroupLayout,
    material: wgpu::BindGroupLayout,
    mask_material: wgpu::BindGroupLayout,
}

impl SceneLayouts {
    pub(super) fn new(device: &wgpu::Device) -> Self {
        use shaders_gen::forward::prez;
        let layout = |variant: &codegen::rt::Variant, group: u32| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(variant.module),
                entries: &bind_group_layout_entries(variant, group),
            })
        };
        // Groups 1 and 2 are the same in every forward variant; group 2 of the masked pre-Z.
        #[expect(
            clippy::expect_used,
            reason = "the naive, opaque, plain forward variant is never excluded"
        )]
        let forward_variant = forward::variant(forward::VariantKey {
            list: forward::List::List0,
            blend: false,
            scalarize: false,
        })
        .expect("the naive, opaque, plain forward variant always exists");
        let mask = prez::variant(prez::VariantKey { alpha_mask: true });
        Self {
            draw: layout(forward_variant, 1),
            material: layout(forward_variant, 2),
            mask_material: layout(mask, 2),
        }
    }
}

pub(super) fn prepare_material(
    device: &wgpu::Device,
    layouts: &SceneLayouts,
    gpu: &GpuScene,
    defaults: &Defaults,
    samplers: &mut Samplers,
    m: &Material,
) -> PreparedMaterial {
    let uniform = material_uniform(m);
    let cutoff = uniform.alpha_cutoff;
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
    // Bindings 6–10: each texture's sampler, in the order of the views.
    let samplers = [
        m.base_color_texture,
        m.normal_texture,
        m.metallic_roughness_texture,
        m.occlusion_texture,
        m.emissive_texture,
    ]
    .map(|t| samplers.of(device, t));
    entries.extend(
        samplers
            .iter()
            .enumerate()
            .map(|(i, s)| wgpu::BindGroupEntry {
                binding: i as u32 + 6,
                resource: wgpu::BindingResource::Sampler(s),
            }),
    );
    let prez_mask_group = matches!(m.alpha_mode, AlphaMode::Mask { .. })
        .then(|| mask_group(device, layouts, m, cutoff, &views[0], &samplers[0]));
    PreparedMaterial {
        prez_mask_group,
        bind_group: device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("material"),
            layout: &layouts.material,
            entries: &entries,
        }),
        alpha_mode: m.alpha_mode,
        double_sided: m.double_sided,
    }
}

/// Group 2 of the masked pre-Z and masked shadow-caster programs (one layout): the material's
/// alpha, cutoff, and base colour texture with its coordinates and sampler.
fn mask_group(
    device: &wgpu::Device,
    layouts: &SceneLayouts,
    m: &Material,
    cutoff: f32,
    base_color: &wgpu::TextureView,
    sampler: &wgpu::Sampler,
) -> wgpu::BindGroup {
    let mask = MaskMaterial::new(m.base_color, uv_map(m.base_color_texture), cutoff);
    let mask_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("mask material"),
        contents: bytemuck::bytes_of(&mask),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("pre-z mask material"),
        layout: &layouts.mask_material,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: mask_buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(base_color),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::Sampler(sampler),
            },
        ],
    })
}
