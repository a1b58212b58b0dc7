//! Scenes from glTF 2.0: meshes, materials with their textures, node transforms, cameras and
//! `KHR_lights_punctual` lights, as plain CPU data ready to upload.
//!
//! [`Scene::load`] reads a `.gltf` or `.glb` file; anything malformed is a [`SceneError`] naming
//! the file and the problem, never a panic. [`GpuScene::upload`] puts it on the GPU.

mod camera;
mod error;
mod free_ranges;
mod gpu;
mod image_formats;
mod instancing;
pub(crate) mod limits;
mod load;
mod load_checks;
mod material_atlas;
mod material_load;
mod mips;
mod modes;
mod morph;
pub mod procedural;
mod resources;
mod tangents;
mod texture;
mod uv_sets;
mod vertex_attrs;
mod warning;

pub use camera::{CameraProjection, SceneCamera};
pub use error::SceneError;
pub use gpu::{GeometryBuffers, GpuPrimitive, GpuScene, VertexStreams};
pub use material_atlas::{AtlasError, AtlasGrowth, AtlasKey, MaterialAtlas};
pub use texture::{Filter, TextureSampler, UvTransform, Wrap};
pub use warning::SceneWarning;

use glam::{Mat4, Vec2, Vec3, Vec4};

/// An axis-aligned bounding box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    pub const EMPTY: Self = Self {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }

    #[must_use]
    pub fn with_point(self, p: Vec3) -> Self {
        Self {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    #[must_use]
    pub fn union(self, other: Self) -> Self {
        Self {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// The box around this one transformed by `m`.
    #[must_use]
    pub fn transformed(self, m: Mat4) -> Self {
        if self.is_empty() {
            return self;
        }
        (0..8).fold(Self::EMPTY, |b, i| {
            let corner = Vec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            );
            b.with_point(m.transform_point3(corner))
        })
    }

    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }
}

/// Triangles of one material, indexed.
#[derive(Debug, Clone, PartialEq)]
pub struct Primitive {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    /// `TEXCOORD_0` (zero where the file has none).
    pub uvs: Vec<Vec2>,
    /// `TEXCOORD_1` (any glTF component type, as floats); empty when the file has none.
    pub uvs1: Vec<Vec2>,
    /// `COLOR_0` as linear RGBA (alpha 1 where the file gives RGB); empty when the file has
    /// none, which draws as white.
    pub colors: Vec<Vec4>,
    /// xyz tangent and handedness in w; generated (MikkTSpace) when the file has none.
    pub tangents: Vec<Vec4>,
    pub indices: Vec<u32>,
    pub material: Option<usize>,
    pub bounds: Aabb,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    pub name: String,
    pub primitives: Vec<Primitive>,
}

/// A mesh placed in the world: one per node with a mesh, or one per instance of a node's
/// `EXT_mesh_gpu_instancing` (node world × the instance's translation × rotation × scale).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Instance {
    pub mesh: usize,
    pub world_from_mesh: Mat4,
}

/// A texture a material samples: an image, the UV set it uses, its sampler and its
/// `KHR_texture_transform`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TextureRef {
    pub image: usize,
    /// 0: `TEXCOORD_0`, 1: `TEXCOORD_1` (after the transform's own `texCoord`, if any). Never
    /// more than 1: the loader points sets it does not load at 0, with a warning. A primitive
    /// without `TEXCOORD_1` (invalid glTF where a texture names set 1; also warned) samples
    /// `TEXCOORD_0` for set 1.
    pub tex_coord: u32,
    pub sampler: TextureSampler,
    pub transform: UvTransform,
}

impl TextureRef {
    /// `image` through `TEXCOORD_0` with the default sampler and no transform.
    pub fn new(image: usize) -> Self {
        Self {
            image,
            tex_coord: 0,
            sampler: TextureSampler::default(),
            transform: UvTransform::IDENTITY,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AlphaMode {
    Opaque,
    /// Discard fragments whose alpha is below the cutoff.
    Mask {
        cutoff: f32,
    },
    /// Blended after opaque geometry, back to front.
    Blend,
}

/// A metallic-roughness PBR material.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub name: String,
    pub base_color: Vec4,
    pub base_color_texture: Option<TextureRef>,
    pub metallic: f32,
    pub roughness: f32,
    pub metallic_roughness_texture: Option<TextureRef>,
    pub normal_texture: Option<TextureRef>,
    pub normal_scale: f32,
    pub occlusion_texture: Option<TextureRef>,
    pub occlusion_strength: f32,
    pub emissive: Vec3,
    pub emissive_texture: Option<TextureRef>,
    pub alpha_mode: AlphaMode,
    pub double_sided: bool,
    /// A material program written in the shader DSL that shades this material instead of
    /// glTF PBR, with this material's parameters (`None`: glTF metallic-roughness). The
    /// factors and textures above still reach it (its `MaterialPoint::material`), and the alpha
    /// mode and sidedness apply as for glTF.
    pub custom: Option<CustomShading>,
}

/// The shading of a material written in the shader DSL (`#[shader_dsl::material]`), registered
/// with the renderer as a `materials::MaterialProgram`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CustomShading {
    /// The program's module name (`MaterialProgram::name`).
    pub program: String,
    /// The material's parameter record: the bytes of the program's `params` struct (its
    /// generated host struct, `bytemuck::bytes_of`), empty for a program without one.
    pub params: Vec<u8>,
}

impl CustomShading {
    /// The shading of `program` (a module name) with parameters `params`.
    pub fn new(program: impl Into<String>, params: &impl bytemuck::Pod) -> Self {
        Self {
            program: program.into(),
            params: bytemuck::bytes_of(params).to_vec(),
        }
    }

    /// The shading of `program`, which takes no parameters.
    pub fn without_params(program: impl Into<String>) -> Self {
        Self {
            program: program.into(),
            params: Vec::new(),
        }
    }
}

/// An image decoded to RGBA8.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub rgba8: Vec<u8>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightKind {
    Point,
    Spot { inner_cone: f32, outer_cone: f32 },
    Directional,
}

/// A `KHR_lights_punctual` light in world space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SceneLight {
    pub kind: LightKind,
    pub position: Vec3,
    /// Direction the light points to (spot and directional).
    pub direction: Vec3,
    pub color: Vec3,
    pub intensity: f32,
    /// `None`: infinite range (the file set none).
    pub range: Option<f32>,
    /// Whether the light casts a shadow (glTF lights do; procedural ones only when picked,
    /// `frame::setup::pick_shadowed`). The shadow pass may still degrade or drop a shadow
    /// when the atlas is full, and reports it.
    pub casts_shadow: bool,
}

/// A loaded glTF scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// The file's meshes in order (morph targets applied at the mesh's default `weights`),
    /// then one morphed copy per node whose own `weights` differ from its mesh's.
    pub meshes: Vec<Mesh>,
    pub materials: Vec<Material>,
    pub images: Vec<Image>,
    pub instances: Vec<Instance>,
    pub cameras: Vec<SceneCamera>,
    pub lights: Vec<SceneLight>,
    /// World-space bounds of every instance.
    pub bounds: Aabb,
    /// What the file holds that is skipped or approximated, in the order found; tools print
    /// these when they open the scene.
    pub warnings: Vec<SceneWarning>,
}

impl Scene {
    /// Number of triangles over all instances.
    pub fn triangle_count(&self) -> usize {
        self.instances
            .iter()
            .flat_map(|i| &self.meshes[i.mesh].primitives)
            .map(|p| p.indices.len() / 3)
            .sum()
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
            custom: None,
        }
    }
}
