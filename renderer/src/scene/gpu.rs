//! A loaded [`Scene`] on the GPU: one buffer per vertex attribute (so each pass binds only what
//! its shader reads), index buffers, and every image as a texture with a full mip chain and the
//! views materials need (sRGB for colour, linear for data).
//!
//! A primitive without `TEXCOORD_1` draws with its `TEXCOORD_0` buffer in that stream, and one
//! without `COLOR_0` with a shared all-white buffer (as long as the scene's largest primitive).

use wgpu::util::DeviceExt as _;

use super::{Scene, TextureRef};

/// One primitive's buffers.
#[derive(Debug)]
pub struct GpuPrimitive {
    pub positions: wgpu::Buffer,
    pub normals: wgpu::Buffer,
    pub uvs: wgpu::Buffer,
    /// `TEXCOORD_1`, where the primitive has it.
    pub uvs1: Option<wgpu::Buffer>,
    /// `COLOR_0` (linear RGBA, `Float32x4`), where the primitive has it.
    pub colors: Option<wgpu::Buffer>,
    pub tangents: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub index_count: u32,
    pub material: Option<usize>,
}

/// An image as a texture (every mip level), with a linear and an sRGB view.
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
    /// White `COLOR_0` for primitives without one, one per vertex of the largest primitive.
    pub white: wgpu::Buffer,
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
                        uvs1: (!p.uvs1.is_empty())
                            .then(|| buffer("uvs1", bytemuck::cast_slice(&p.uvs1), vertex)),
                        colors: (!p.colors.is_empty())
                            .then(|| buffer("colors", bytemuck::cast_slice(&p.colors), vertex)),
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
        let vertices = scene
            .meshes
            .iter()
            .flat_map(|m| &m.primitives)
            .map(|p| p.positions.len())
            .max()
            .unwrap_or(0)
            .max(1);
        let white = buffer(
            "white colors",
            bytemuck::cast_slice(&vec![glam::Vec4::ONE; vertices]),
            vertex,
        );
        let colour_images = colour_images(scene);
        let images = scene
            .images
            .iter()
            .enumerate()
            .map(|(index, image)| {
                upload_image(device, queue, image, colour_images.contains(&index))
            })
            .collect();
        Self {
            meshes,
            images,
            white,
        }
    }

    /// The vertex streams of `vs_forward`: position, normal, `TEXCOORD_0`, tangent,
    /// `TEXCOORD_1`, `COLOR_0` ([`Self::uvs1`], [`Self::colors`]).
    pub fn forward_streams<'a>(&'a self, p: &'a GpuPrimitive) -> [&'a wgpu::Buffer; 6] {
        [
            &p.positions,
            &p.normals,
            &p.uvs,
            &p.tangents,
            self.uvs1(p),
            self.colors(p),
        ]
    }

    /// The vertex streams of the masked depth passes (pre-Z and shadow casters): position,
    /// `TEXCOORD_0`, `TEXCOORD_1`, `COLOR_0`.
    pub fn mask_streams<'a>(&'a self, p: &'a GpuPrimitive) -> [&'a wgpu::Buffer; 4] {
        [&p.positions, &p.uvs, self.uvs1(p), self.colors(p)]
    }

    /// `p`'s `TEXCOORD_1` stream: its own, else its `TEXCOORD_0`.
    pub fn uvs1<'a>(&'a self, p: &'a GpuPrimitive) -> &'a wgpu::Buffer {
        p.uvs1.as_ref().unwrap_or(&p.uvs)
    }

    /// `p`'s `COLOR_0` stream: its own, else white.
    pub fn colors<'a>(&'a self, p: &'a GpuPrimitive) -> &'a wgpu::Buffer {
        p.colors.as_ref().unwrap_or(&self.white)
    }

    /// The view a material slot samples: sRGB for colour textures, linear for data.
    pub fn view(&self, texture: TextureRef, colour: bool) -> &wgpu::TextureView {
        let image = &self.images[texture.image];
        if colour { &image.srgb } else { &image.linear }
    }
}

/// The images some material uses as colour (base colour or emissive): their mip levels are
/// averaged in linear light. An image used only as data (normals, metallic-roughness,
/// occlusion) is averaged as stored.
fn colour_images(scene: &Scene) -> std::collections::HashSet<usize> {
    scene
        .materials
        .iter()
        .flat_map(|m| [m.base_color_texture, m.emissive_texture])
        .flatten()
        .map(|t| t.image)
        .collect()
}

/// `image` as a texture with its full mip chain (`colour`: averaged in linear light) and its
/// linear and sRGB views.
fn upload_image(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    image: &super::Image,
    colour: bool,
) -> GpuImage {
    let texture = device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some("scene image"),
            size: wgpu::Extent3d {
                width: image.width,
                height: image.height,
                depth_or_array_layers: 1,
            },
            mip_level_count: super::mips::level_count(image.width, image.height),
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[wgpu::TextureFormat::Rgba8UnormSrgb],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &super::mips::mip_chain(image, colour),
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
}
