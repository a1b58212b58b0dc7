//! Adding meshes, materials and images to the prepared scene between frames, replacing
//! materials, and removing meshes and materials, as an engine streams a level in and out: each
//! upload writes only what it adds (into room that removed meshes and textures gave back, else
//! the geometry streams grow by doubling, copied on the GPU) and the passes keep what they
//! built for the scene, which keeps its identity. Instances of an added mesh are then added by handle
//! ([`Renderer::add_instance`]).

use crate::frame_data::InputError;
use std::sync::Arc;

use super::Renderer;
use crate::frame_data::{PreparedScene, RenderError};
use crate::scene::{Image, Material, Mesh};

/// How much of the shared geometry streams meshes hold ([`Renderer::geometry_usage`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GeometryUsage {
    /// Vertices held by meshes.
    pub vertices: u64,
    /// Indices held by meshes.
    pub indices: u64,
    /// Vertices the streams have room for, taken or free (grows by doubling).
    pub vertex_capacity: u64,
    /// Indices the streams have room for, taken or free (grows by doubling).
    pub index_capacity: u64,
}

impl Renderer {
    /// Adds `mesh` to the prepared scene, from the next frame, and returns its mesh index for
    /// [`Renderer::add_instance`]. Its primitives name materials by index: the scene's
    /// materials, then the glTF default material ([`Renderer::default_material`]), then those
    /// added with [`Renderer::add_material`]; a primitive without one uses the default.
    /// Inconsistent data (attribute lengths, indices past the vertices, an unknown material)
    /// and geometry past the device's buffer limits are refused with [`InputError::Scene`](crate::frame::InputError::Scene).
    pub fn add_mesh(&mut self, mesh: &Mesh) -> Result<usize, RenderError> {
        let gpu = self.gpu.clone();
        Ok(self
            .prepared_mut()?
            .add_mesh(gpu.device(), gpu.queue(), mesh)?)
    }

    /// Adds `material` to the prepared scene and returns its index for an added mesh's
    /// primitives. Its textures name the scene's images, then those added with
    /// [`Renderer::add_image`]. A material shaded by a material program names a registered
    /// one ([`Renderer::register_material`]) with a parameter record of its size
    /// ([`InputError::Material`](crate::frame::InputError::Material)).
    pub fn add_material(&mut self, material: &Material) -> Result<usize, RenderError> {
        crate::materials::check_material(material, &self.materials)?;
        let gpu = self.gpu.clone();
        Ok(self
            .prepared_mut()?
            .add_material(gpu.device(), gpu.queue(), material)?)
    }

    /// Replaces material `index` of the prepared scene (as [`Renderer::add_mesh`] numbers
    /// materials) from the next frame: its parameters and textures, or its alpha mode and
    /// sidedness or material program (its draws then move to other batches). Nothing else is
    /// uploaded.
    pub fn set_material(&mut self, index: usize, material: &Material) -> Result<(), RenderError> {
        crate::materials::check_material(material, &self.materials)?;
        let gpu = self.gpu.clone();
        Ok(self
            .prepared_mut()?
            .set_material(gpu.device(), gpu.queue(), index, material)?)
    }

    /// Removes mesh `mesh` from the prepared scene: its vertices and indices are given back, and
    /// later meshes take that room before the streams grow. Its index is not reused: adding an
    /// instance of it is [`InputError::MeshRemoved`](crate::frame::InputError::MeshRemoved). A mesh that live instances still use is
    /// [`InputError::MeshInUse`](crate::frame::InputError::MeshInUse) (remove them first); an unknown or removed one is
    /// [`InputError::Scene`](crate::frame::InputError::Scene).
    pub fn remove_mesh(&mut self, mesh: usize) -> Result<(), RenderError> {
        let (_, table) = self
            .scene
            .as_ref()
            .ok_or(RenderError::Input(InputError::NoScene))?;
        let instances = table.instances_of(mesh);
        if instances > 0 {
            return Err(RenderError::Input(InputError::MeshInUse {
                mesh,
                instances,
            }));
        }
        Ok(self.prepared_mut()?.remove_mesh(mesh)?)
    }

    /// Removes material `index` from the prepared scene: the next [`Renderer::add_material`]
    /// takes its index, and the material atlas releases the textures no other material
    /// samples (later textures take their room). Refused with [`InputError::Scene`](crate::frame::InputError::Scene) while a
    /// mesh of the scene or an instance ([`Renderer::set_instance_material`]) draws with it (remove the mesh, or replace the material with
    /// [`Renderer::set_material`]), for the default material, and for an unknown or removed
    /// index.
    pub fn remove_material(&mut self, index: usize) -> Result<(), RenderError> {
        let (prepared, table) = self
            .scene
            .as_ref()
            .ok_or(RenderError::Input(InputError::NoScene))?;
        // An instance that draws with it instead of its mesh's material (the meshes' own use
        // is the prepared scene's check).
        let given = table.states.iter().enumerate().find(|(_, s)| {
            let templates = prepared
                .mesh_draws
                .get(s.mesh)
                .map_or(&[][..], Vec::as_slice);
            s.live
                && (table.draws[s.draws()].iter().zip(templates))
                    .any(|(d, t)| d.material == index && t.material != index)
        });
        if let Some((instance, _)) = given {
            return Err(crate::scene::SceneError::Inconsistent(format!(
                "material {index} is drawn by instance {instance} (`set_instance_material`): give it another material first"
            ))
            .into());
        }
        let gpu = self.gpu.clone();
        Ok(self
            .prepared_mut()?
            .remove_material(gpu.device(), gpu.queue(), index)?)
    }

    /// The prepared scene's geometry streams: vertices and indices held by meshes, and the
    /// room the streams have (taken or free).
    pub fn geometry_usage(&self) -> Result<GeometryUsage, RenderError> {
        let (prepared, _) = self
            .scene
            .as_ref()
            .ok_or(RenderError::Input(InputError::NoScene))?;
        let geometry = &prepared.gpu.geometry;
        let (vertices, indices) = geometry.counts();
        let (vertex_capacity, index_capacity) = geometry.capacity();
        Ok(GeometryUsage {
            vertices,
            indices,
            vertex_capacity,
            index_capacity,
        })
    }

    /// Keeps `image` and returns its index for an added material's textures. It is packed
    /// into the material atlas (with its mip chain, averaged in linear light where a material
    /// reads it as colour) with the first material that uses it.
    pub fn add_image(&mut self, image: &Image) -> Result<usize, RenderError> {
        let gpu = self.gpu.clone();
        Ok(self.prepared_mut()?.add_image(gpu.device(), image)?)
    }

    /// The prepared scene's material atlas: its pages, each texture's index, and how often
    /// textures were added to it in place.
    pub fn material_atlas(&self) -> Result<&crate::scene::MaterialAtlas, RenderError> {
        let (prepared, _) = self
            .scene
            .as_ref()
            .ok_or(RenderError::Input(InputError::NoScene))?;
        Ok(prepared.material_atlas())
    }

    /// The index of the glTF default material in the prepared scene's materials (after the
    /// scene's own).
    pub fn default_material(&self) -> Result<usize, RenderError> {
        let (prepared, _) = self
            .scene
            .as_ref()
            .ok_or(RenderError::Input(InputError::NoScene))?;
        Ok(prepared.default_material)
    }

    /// The prepared scene, to change (copied first if a frame still holds it: its GPU
    /// objects are shared, not copied).
    fn prepared_mut(&mut self) -> Result<&mut PreparedScene, RenderError> {
        let (prepared, _) = self
            .scene
            .as_mut()
            .ok_or(RenderError::Input(InputError::NoScene))?;
        Ok(Arc::make_mut(prepared))
    }
}
