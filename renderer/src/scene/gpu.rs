//! A loaded [`Scene`] on the GPU: one buffer per vertex attribute (so each pass binds only what
//! its shader reads), index buffers, and every image as a texture with the views materials need
//! (sRGB for colour, linear for data).

use wgpu::util::DeviceExt as _;

use super::{Scene, TextureRef};

/// One primitive's buffers.
#[derive(Debug)]
pub struct GpuPrimitive {
    pub positions: wgpu::Buffer,
    pub normals: wgpu::Buffer,
    pub uvs: wgpu::Buffer,
    pub tangents: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub index_count: u32,
    pub material: Option<usize>,
}

/// An image as a texture, with a linear and an sRGB view.
#[derive(Debug)]
pub struct GpuImage {
    pub texture: wgpu::Texture,
    /// For data: normals, metallic-roughness, occlusion.
    pub linear: wgpu::TextureView,
    /// For colour: base colour, emissive.
    pub srgb: wgpu::TextureView,
}

/// Every mesh primitive and image of a scene, uploaded.
#[derive(Debug)]
pub struct GpuScene {
    /// `meshes[m][p]` is primitive `p` of mesh `m`.
    pub meshes: Vec<Vec<GpuPrimitive>>,
    pub images: Vec<GpuImage>,
}

impl GpuScene {
    pub fn upload(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene) -> Self {
        let buffer = |label: &str, bytes: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage: usage | wgpu::BufferUsages::COPY_SRC,
            })
        };
        let vertex = wgpu::BufferUsages::VERTEX;
        let meshes = scene
            .meshes
            .iter()
            .map(|mesh| {
                mesh.primitives
                    .iter()
                    .map(|p| GpuPrimitive {
                        positions: buffer("positions", bytemuck::cast_slice(&p.positions), vertex),
                        normals: buffer("normals", bytemuck::cast_slice(&p.normals), vertex),
                        uvs: buffer("uvs", bytemuck::cast_slice(&p.uvs), vertex),
                        tangents: buffer("tangents", bytemuck::cast_slice(&p.tangents), vertex),
                        indices: buffer(
                            "indices",
                            bytemuck::cast_slice(&p.indices),
                            wgpu::BufferUsages::INDEX,
                        ),
                        index_count: p.indices.len() as u32,
                        material: p.material,
                    })
                    .collect()
            })
            .collect();
        let images = scene
            .images
            .iter()
            .map(|image| {
                let texture = device.create_texture_with_data(
                    queue,
                    &wgpu::TextureDescriptor {
                        label: Some("scene image"),
                        size: wgpu::Extent3d {
                            width: image.width,
                            height: image.height,
                            depth_or_array_layers: 1,
                        },
                        mip_level_count: 1,
                        sample_count: 1,
                        dimension: wgpu::TextureDimension::D2,
                        format: wgpu::TextureFormat::Rgba8Unorm,
                        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC,
                        view_formats: &[wgpu::TextureFormat::Rgba8UnormSrgb],
                    },
                    wgpu::util::TextureDataOrder::LayerMajor,
                    &image.rgba8,
                );
                let srgb = texture.create_view(&wgpu::TextureViewDescriptor {
                    format: Some(wgpu::TextureFormat::Rgba8UnormSrgb),
                    ..Default::default()
                });
                GpuImage {
                    linear: texture.create_view(&Default::default()),
                    srgb,
                    texture,
                }
            })
            .collect();
        Self { meshes, images }
    }

    /// The view a material slot samples: sRGB for colour textures, linear for data.
    pub fn view(&self, texture: TextureRef, colour: bool) -> &wgpu::TextureView {
        let image = &self.images[texture.image];
        if colour { &image.srgb } else { &image.linear }
    }
}
