//! Scenes from glTF 2.0: meshes, materials with their textures, node transforms, cameras and
//! `KHR_lights_punctual` lights, as plain CPU data ready to upload.
//!
//! [`Scene::load`] reads a `.gltf` or `.glb` file; anything malformed is a [`SceneError`] naming
//! the file and the problem, never a panic. `GpuScene::upload` puts it on the GPU.

mod camera;
mod error;
mod free_ranges;
mod gpu;
#[cfg(feature = "gltf")]
mod image_formats;
#[cfg(feature = "gltf")]
mod instancing;
pub(crate) mod limits;
#[cfg(feature = "gltf")]
mod load;
#[cfg(feature = "gltf")]
mod load_checks;
mod material_atlas;
#[cfg(feature = "gltf")]
mod material_load;
mod mips;
#[cfg(feature = "gltf")]
mod modes;
#[cfg(feature = "gltf")]
mod morph;
pub mod procedural;
#[cfg(feature = "gltf")]
mod resources;
#[cfg(feature = "gltf")]
mod tangents;
mod texture;
#[cfg(feature = "gltf")]
mod uv_sets;
#[cfg(feature = "gltf")]
mod vertex_attrs;
mod warning;

pub use camera::{CameraProjection, SceneCamera};
pub use error::SceneError;
internal_use!(gpu::{GpuPrimitive, GpuScene, VertexStreams});
internal_use!(material_atlas::{AtlasGrowth, AtlasKey, MaterialAtlas});
pub use texture::{Filter, TextureSampler, UvTransform, Wrap};
pub use warning::SceneWarning;
#[cfg(feature = "internals")]
#[doc(hidden)]
pub use {gpu::GeometryBuffers, material_atlas::AtlasError};

use glam::{Mat4, Vec2, Vec3, Vec4};

/// An axis-aligned bounding box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// The smallest corner (least x, y and z).
    pub min: Vec3,
    /// The largest corner (greatest x, y and z).
    pub max: Vec3,
}

impl Aabb {
    /// The box around no point (`min` +∞, `max` −∞): the start for [`Aabb::with_point`] and
    /// [`Aabb::union`], which it leaves unchanged.
    pub const EMPTY: Self = Self {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// Whether the box holds no point, as [`Aabb::EMPTY`] does.
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }

    /// The smallest box that holds this one and `p`.
    #[must_use]
    pub fn with_point(self, p: Vec3) -> Self {
        Self {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// The smallest box that holds this one and `other`.
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

    /// The midpoint of `min` and `max` (NaN for an empty box).
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }
}

/// Triangles of one material, indexed.
#[derive(Debug, Clone, PartialEq)]
pub struct Primitive {
    /// `POSITION` in mesh space (glTF units: metres).
    pub positions: Vec<Vec3>,
    /// `NORMAL` in mesh space, one per position; flat face normals when the file has none.
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
    /// A triangle list (strips and fans converted) of indices into this primitive's vertices;
    /// front faces wind counter-clockwise, as in glTF.
    pub indices: Vec<u32>,
    /// Index into [`Scene::materials`]; `None`: the glTF default material
    /// ([`Material::gltf_default`]), which the renderer adds after the scene's own.
    pub material: Option<usize>,
    /// Mesh-space box around `positions`.
    pub bounds: Aabb,
}

/// A glTF mesh: its triangle primitives, in mesh space.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// The file's name for the mesh, or `#<index>` when it has none; used in messages.
    pub name: String,
    /// The drawn primitives in file order (points and lines are skipped with a warning); empty
    /// for a mesh no node uses.
    pub primitives: Vec<Primitive>,
}

/// A mesh placed in the world: one per node with a mesh, or one per instance of a node's
/// `EXT_mesh_gpu_instancing` (node world × the instance's translation × rotation × scale).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Instance {
    /// Index into [`Scene::meshes`].
    pub mesh: usize,
    /// The transform from mesh space to world space.
    pub world_from_mesh: Mat4,
}

/// A texture a material samples: an image, the UV set it uses, its sampler and its
/// `KHR_texture_transform`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TextureRef {
    /// Index into [`Scene::images`].
    pub image: usize,
    /// 0: `TEXCOORD_0`, 1: `TEXCOORD_1` (after the transform's own `texCoord`, if any). Never
    /// more than 1: the loader points sets it does not load at 0, with a warning. A primitive
    /// without `TEXCOORD_1` (invalid glTF where a texture names set 1; also warned) samples
    /// `TEXCOORD_0` for set 1.
    pub tex_coord: u32,
    /// Wrap and filter modes (the glTF texture's sampler).
    pub sampler: TextureSampler,
    /// Applied to the UVs before sampling; [`UvTransform::IDENTITY`] when the file has none.
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

/// How a material's alpha (base colour factor × texture × vertex colour) is used (glTF
/// `alphaMode`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AlphaMode {
    /// Alpha is ignored: the surface is fully opaque (glTF's default).
    Opaque,
    /// Discard fragments whose alpha is below the cutoff.
    Mask {
        /// glTF `alphaCutoff` (0.5 when the file sets none).
        cutoff: f32,
    },
    /// Blended after opaque geometry, back to front.
    Blend,
}

/// A metallic-roughness PBR material.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// The file's name (empty when it has none).
    pub name: String,
    /// Linear RGBA factor, multiplied with the base colour texture (glTF `baseColorFactor`).
    pub base_color: Vec4,
    /// sRGB colour texture; its alpha multiplies `base_color`'s.
    pub base_color_texture: Option<TextureRef>,
    /// Metalness factor in `[0, 1]`, multiplied with the texture's blue channel.
    pub metallic: f32,
    /// Perceptual roughness factor in `[0, 1]`, multiplied with the texture's green channel.
    pub roughness: f32,
    /// Linear data texture: roughness in green, metalness in blue (glTF layout).
    pub metallic_roughness_texture: Option<TextureRef>,
    /// Tangent-space normal map (linear data, glTF conventions).
    pub normal_texture: Option<TextureRef>,
    /// Scales the normal map's x and y (glTF `normalTexture.scale`, default 1).
    pub normal_scale: f32,
    /// Linear ambient occlusion in the red channel.
    pub occlusion_texture: Option<TextureRef>,
    /// How much occlusion applies, 0 (none) to 1 (full; glTF's default).
    pub occlusion_strength: f32,
    /// Linear RGB emission factor, already multiplied by `KHR_materials_emissive_strength`.
    pub emissive: Vec3,
    /// sRGB colour texture multiplied with `emissive`.
    pub emissive_texture: Option<TextureRef>,
    /// How alpha is used: opaque, masked or blended.
    pub alpha_mode: AlphaMode,
    /// Back faces are drawn too (not culled), as glTF `doubleSided`.
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
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width × height × 4` bytes, row by row, as stored: read as sRGB where a material samples
    /// it as colour (base colour, emissive), as linear data elsewhere.
    pub rgba8: Vec<u8>,
}

/// The type of a [`SceneLight`], as `KHR_lights_punctual` defines it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightKind {
    /// Emits in every direction from its position.
    Point,
    /// A cone around its direction: full intensity within `inner_cone`, fading to none at
    /// `outer_cone`.
    Spot {
        /// Angle from the axis where the falloff starts, radians (glTF default 0).
        inner_cone: f32,
        /// Angle from the axis where the light ends, radians (glTF default π/4).
        outer_cone: f32,
    },
    /// Parallel light along its direction, from infinitely far; position and range are unused.
    Directional,
}

/// A `KHR_lights_punctual` light in world space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SceneLight {
    /// Point, spot or directional.
    pub kind: LightKind,
    /// World-space position (the node's origin).
    pub position: Vec3,
    /// Direction the light points to (spot and directional).
    pub direction: Vec3,
    /// Linear RGB colour (glTF default white).
    pub color: Vec3,
    /// glTF units: candela for point and spot lights, lux for directional ones.
    pub intensity: f32,
    /// Distance in metres where the light's influence ends. `None`: infinite range (the file
    /// set none).
    pub range: Option<f32>,
    /// Whether the light casts a shadow (glTF lights do; procedural ones only when picked,
    /// `demo::pick_shadowed`). The shadow pass may still degrade or drop a shadow
    /// when the atlas is full, and reports it.
    pub casts_shadow: bool,
}

/// A loaded glTF scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// The file's meshes in order (morph targets applied at the mesh's default `weights`),
    /// then one morphed copy per node whose own `weights` differ from its mesh's.
    pub meshes: Vec<Mesh>,
    /// The file's materials in order; [`Primitive::material`] indexes them.
    pub materials: Vec<Material>,
    /// The file's images decoded, in order; [`TextureRef::image`] indexes them.
    pub images: Vec<Image>,
    /// Every placed mesh, in node order (parents first).
    pub instances: Vec<Instance>,
    /// The cameras of the scene's nodes, in node order.
    pub cameras: Vec<SceneCamera>,
    /// The lights of the scene's nodes, in node order, in world space.
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
