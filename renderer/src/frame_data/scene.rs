//! A scene prepared for drawing: its GPU geometry, what each mesh draws, and its materials
//! (one buffer of records and the atlas of their textures, `material_groups`), with meshes,
//! materials and images added, meshes and materials removed and materials replaced between
//! frames. Its instances and their draw records are apart, in
//! [`super::InstanceTable`], which an engine edits.

use std::sync::Arc;

use glam::Mat4;
use shaders_gen::forward::forward;

use super::material_groups::{MaterialTable, SceneLayouts};
use super::material_params::CustomPrograms;
use crate::scene::limits::{check_geometry, check_image, check_material, check_mesh};
use crate::scene::{Aabb, AlphaMode, GpuScene, Image, Material, Mesh, Scene, SceneError};

/// Whether `world_from_mesh` mirrors (a negative determinant): glTF 2.0 then has the primitive's
/// front faces wind clockwise, so its draws use the clockwise pipelines and a flipped bitangent.
pub fn is_mirrored(world_from_mesh: Mat4) -> bool {
    world_from_mesh.determinant() < 0.0
}

/// The `Draw` record of a primitive of material `material` placed at `world_from_mesh`.
pub(super) fn draw_uniform(world_from_mesh: Mat4, material: usize) -> forward::Draw {
    forward::Draw::new(
        world_from_mesh,
        world_from_mesh.inverse().transpose(),
        material as u32,
        if is_mirrored(world_from_mesh) {
            -1.0
        } else {
            1.0
        },
    )
}

/// What every instance of a mesh draws, one per primitive.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshDraw {
    pub material: usize,
    /// Where the primitive lies in the scene's shared geometry buffers.
    pub geometry: crate::scene::GpuPrimitive,
    /// The primitive's bounds in mesh space.
    pub local_bounds: Aabb,
}

/// A scene on the GPU, ready for the passes. Meshes, materials and images can be added to it
/// ([`PreparedScene::add_mesh`], [`PreparedScene::add_material`],
/// [`PreparedScene::add_image`]); it keeps its [`PreparedScene::id`] through them, so passes
/// keep what they built for it.
#[derive(Debug, Clone)]
pub struct PreparedScene {
    /// This scene's identity: a new one per `prepare_scene`, the same after additions.
    pub id: u32,
    /// Its geometry and material table on the GPU.
    pub gpu: GpuScene,
    /// `mesh_draws[mesh]`: what an instance of `mesh` draws (its draws in
    /// `super::InstanceTable` follow this order).
    pub mesh_draws: Vec<Vec<MeshDraw>>,
    /// The scene's materials, then the glTF default material (the material of primitives
    /// without one, at [`PreparedScene::default_material`]), then materials added, as given
    /// (their records and textures are on the GPU in the material table).
    pub materials: Vec<Material>,
    /// Index of glTF's default material in `materials`.
    pub default_material: usize,
    /// Bumped when a material changes how its draws are batched (its alpha mode or
    /// sidedness, [`PreparedScene::set_material`]): passes then place every draw again.
    pub placement_revision: u64,
    /// Meshes removed ([`PreparedScene::remove_mesh`]): their indices name nothing.
    removed_meshes: Vec<bool>,
    /// Materials removed ([`PreparedScene::remove_material`]), whose indices the next added
    /// materials take (each holds the default material meanwhile, which nothing draws with).
    free_materials: Vec<usize>,
    /// The layouts the material groups are built against.
    layouts: SceneLayouts,
    /// The scene's images (added ones after them), kept for packing the atlas again when a
    /// material brings a texture it does not hold.
    images: Vec<Arc<Image>>,
    table: MaterialTable,
    /// The material programs the materials name, and their parameter records.
    custom: CustomPrograms,
}

impl PreparedScene {
    /// The layout of group 1 (the draw records) of the geometry programs.
    pub fn draw_layout(&self) -> &wgpu::BindGroupLayout {
        &self.layouts.draw
    }

    /// Whether any material is alpha-blended (drawn after the opaque surfaces, absent from the
    /// pre-Z depth).
    pub fn has_blended(&self) -> bool {
        self.materials
            .iter()
            .any(|m| m.alpha_mode == AlphaMode::Blend)
    }

    /// Group 2 of the forward and G-buffer programs: every material's record and texture.
    pub fn material_group(&self) -> &wgpu::BindGroup {
        &self.table.group
    }

    /// The material program number of material `index` (what splits the draw batches): 0 for
    /// glTF PBR, else from 1 in the order the scene first named each program.
    pub fn material_program(&self, index: usize) -> u32 {
        self.materials
            .get(index)
            .map_or(0, |m| self.custom.program_of(m))
    }

    /// The module name of material program `program` (from 1).
    pub fn material_program_name(&self, program: u32) -> Option<&str> {
        self.custom.name(program)
    }

    /// The module names of the material programs the scene's materials have named.
    pub fn material_program_names(&self) -> impl Iterator<Item = &str> {
        self.custom.names()
    }

    /// The parameter records of material program `program` (group 3's `PARAMS`), if it takes
    /// parameters.
    pub fn material_params(&self, program: u32) -> Option<&wgpu::Buffer> {
        self.custom.buffer(program)
    }

    /// Group 2 (every material's record and texture) of `program`, a program whose layout
    /// differs from the geometry passes' (a compute program's).
    pub fn material_group_for(
        &self,
        device: &wgpu::Device,
        program: &crate::shader::ShaderProgram,
    ) -> Result<wgpu::BindGroup, shader_bind::BindError> {
        self.table.group_for(device, program)
    }

    /// Group 2 of the masked pre-Z and masked shadow-caster programs.
    pub fn mask_group(&self) -> &wgpu::BindGroup {
        &self.table.mask_group
    }

    /// Uploads `scene`'s geometry, writes its materials' records and packs their textures into
    /// the material atlas, with bind groups against the layouts the DSL reflects for the
    /// forward program's groups 1 (the draw records) and 2 (materials), which the pre-Z and
    /// shadow-caster programs share for group 1, and the masked pre-Z program's group 2.
    ///
    /// `scene` must have passed [`Scene::check_for_device`] (`Renderer::prepare_scene` checks);
    /// the atlas can still refuse textures that need more layers than the device has.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
    ) -> Result<Arc<Self>, SceneError> {
        let layouts = SceneLayouts::new(device);
        let gpu = GpuScene::upload(device, scene);
        // Primitives without a material use the glTF default material, last (`draw_plan`).
        let mut materials = scene.materials.clone();
        materials.push(Material::gltf_default());
        let images: Vec<Arc<Image>> = scene.images.iter().cloned().map(Arc::new).collect();
        let custom = CustomPrograms::new(device, queue, &materials)?;
        let programs: Vec<u32> = materials.iter().map(|m| custom.program_of(m)).collect();
        let table = MaterialTable::new(device, queue, &layouts, &images, (&materials, &programs))?;
        // Primitives without a material use the glTF default material, last.
        let default_material = scene.materials.len();
        let mesh_draws = scene
            .meshes
            .iter()
            .zip(&gpu.meshes)
            .map(|(mesh, placed)| {
                mesh.primitives
                    .iter()
                    .zip(placed)
                    .map(|(p, &geometry)| MeshDraw {
                        material: p.material.unwrap_or(default_material),
                        geometry,
                        local_bounds: p.bounds,
                    })
                    .collect()
            })
            .collect();
        static NEXT_ID: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(1);
        Ok(Arc::new(Self {
            id: NEXT_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            gpu,
            mesh_draws,
            materials,
            default_material,
            placement_revision: 0,
            removed_meshes: vec![false; scene.meshes.len()],
            free_materials: Vec::new(),
            layouts,
            images,
            table,
            custom,
        }))
    }

    /// Uploads `mesh` after the scene's meshes and returns its index (what
    /// `super::InstanceTable::add` takes). Its primitives name materials by index into
    /// [`PreparedScene::materials`]; one without a material draws with the default material.
    pub fn add_mesh(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: &Mesh,
    ) -> Result<usize, SceneError> {
        check_mesh(mesh, self.materials.len())?;
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            if let Some(m) = primitive
                .material
                .filter(|m| self.free_materials.contains(m))
            {
                return Err(SceneError::Inconsistent(format!(
                    "primitive {p} names material {m}, which was removed"
                )));
            }
        }
        let (vertices, indices) = self.gpu.geometry.counts();
        let new = |f: fn(&crate::scene::Primitive) -> usize| -> u64 {
            mesh.primitives.iter().map(|p| f(p) as u64).sum()
        };
        let limits = device.limits();
        check_geometry(
            vertices + new(|p| p.positions.len()),
            indices + new(|p| p.indices.len()),
            &limits,
        )?;
        let index = self.gpu.add_mesh(device, queue, mesh);
        let draws = mesh
            .primitives
            .iter()
            .zip(&self.gpu.meshes[index])
            .map(|(p, &geometry)| MeshDraw {
                material: p.material.unwrap_or(self.default_material),
                geometry,
                local_bounds: p.bounds,
            })
            .collect();
        self.mesh_draws.push(draws);
        self.removed_meshes.push(false);
        Ok(index)
    }

    /// Whether mesh `mesh` was removed (its index names nothing; no instance may use it).
    pub fn mesh_removed(&self, mesh: usize) -> bool {
        self.removed_meshes.get(mesh).copied().unwrap_or(false)
    }

    /// Removes mesh `mesh`: its vertices and indices are given back for later meshes, and its
    /// index stays, naming nothing (indices are never given to another mesh). The caller
    /// makes sure no live instance uses it.
    pub fn remove_mesh(&mut self, mesh: usize) -> Result<(), SceneError> {
        let count = self.mesh_draws.len();
        if mesh >= count {
            return Err(SceneError::Inconsistent(format!(
                "mesh {mesh} does not exist: the prepared scene has {count} meshes"
            )));
        }
        if self.removed_meshes[mesh] {
            return Err(SceneError::Inconsistent(format!(
                "mesh {mesh} was removed already"
            )));
        }
        self.gpu.remove_mesh(mesh);
        self.mesh_draws[mesh].clear();
        self.removed_meshes[mesh] = true;
        Ok(())
    }

    /// Removes material `index`: its index is given to the next added material, and the atlas
    /// releases the textures no other material samples. Refused for the default material, a
    /// removed one, and one that a mesh still in the scene draws with.
    pub fn remove_material(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        index: usize,
    ) -> Result<(), SceneError> {
        self.check_material_index(index)?;
        if index == self.default_material {
            return Err(SceneError::Inconsistent(format!(
                "material {index} is the glTF default material, which primitives without a \
                 material draw with; it cannot be removed"
            )));
        }
        let user =
            (self.mesh_draws.iter()).position(|draws| draws.iter().any(|d| d.material == index));
        if let Some(mesh) = user {
            return Err(SceneError::Inconsistent(format!(
                "material {index} is drawn by mesh {mesh}: remove that mesh first, or replace \
                 the material (set_material)"
            )));
        }
        self.materials[index] = Material::gltf_default();
        self.write_material(device, queue, index)?;
        self.free_materials.push(index);
        self.table.release_unused(&self.materials);
        Ok(())
    }

    /// Refuses an index past the materials or of a removed material.
    pub fn check_material_index(&self, index: usize) -> Result<(), SceneError> {
        let count = self.materials.len();
        if index >= count {
            return Err(SceneError::Inconsistent(format!(
                "material {index} does not exist: the prepared scene has {count} materials"
            )));
        }
        if self.free_materials.contains(&index) {
            return Err(SceneError::Inconsistent(format!(
                "material {index} was removed"
            )));
        }
        Ok(())
    }

    /// Adds `material` and returns its index (what an added mesh's primitives name): the index
    /// of the last removed material, else one after the others. Its textures name images of
    /// the scene (added ones included).
    pub fn add_material(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        material: &Material,
    ) -> Result<usize, SceneError> {
        check_material(material, self.images.len())?;
        let Some(index) = self.free_materials.pop() else {
            self.materials.push(material.clone());
            let index = self.materials.len() - 1;
            if let Err(e) = self.write_material(device, queue, index) {
                // Nothing changed: the table never held it.
                self.materials.pop();
                return Err(e);
            }
            return Ok(index);
        };
        let removed = std::mem::replace(&mut self.materials[index], material.clone());
        if let Err(e) = self.write_material(device, queue, index) {
            // Nothing changed: the slot still holds the removed material's stand-in.
            self.materials[index] = removed;
            self.free_materials.push(index);
            return Err(e);
        }
        Ok(index)
    }

    /// Replaces material `index` (parameters and textures) in place: its draws draw with the
    /// new one from the next frame. A change of alpha mode, sidedness or material program moves
    /// its draws to other batches (every draw is placed again, once).
    pub fn set_material(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        index: usize,
        material: &Material,
    ) -> Result<(), SceneError> {
        self.check_material_index(index)?;
        check_material(material, self.images.len())?;
        let previous = std::mem::replace(&mut self.materials[index], material.clone());
        if let Err(e) = self.write_material(device, queue, index) {
            // Nothing changed: the table still holds the previous material.
            self.materials[index] = previous;
            return Err(e);
        }
        let program = |m: &Material| m.custom.as_ref().map(|c| c.program.clone());
        if (
            previous.alpha_mode,
            previous.double_sided,
            program(&previous),
        ) != (
            material.alpha_mode,
            material.double_sided,
            program(material),
        ) {
            self.placement_revision += 1;
        }
        Ok(())
    }

    /// Writes material `index`'s record in place (its textures added to the atlas in place
    /// where new), or builds the table again (the atlas packed anew) when the buffer is full
    /// or a new image is larger than an atlas page.
    fn write_material(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        index: usize,
    ) -> Result<(), SceneError> {
        self.custom.write(device, queue, &self.materials, index)?;
        let inputs = (&self.layouts, &self.images[..]);
        let material = &self.materials[index];
        let program = self.custom.program_of(material);
        if !self
            .table
            .write(device, queue, inputs, index, (material, program))
        {
            let programs: Vec<u32> = self
                .materials
                .iter()
                .map(|m| self.custom.program_of(m))
                .collect();
            self.table = MaterialTable::new(
                device,
                queue,
                &self.layouts,
                &self.images,
                (&self.materials, &programs),
            )?;
        }
        Ok(())
    }

    /// The material atlas of the scene's textures.
    pub fn material_atlas(&self) -> &crate::scene::MaterialAtlas {
        &self.table.atlas
    }

    /// Keeps `image` after the scene's images and returns its index (what an added material's
    /// textures name). It reaches the GPU with the first material that uses it.
    pub fn add_image(&mut self, device: &wgpu::Device, image: &Image) -> Result<usize, SceneError> {
        check_image(self.images.len(), image, &device.limits())?;
        self.images.push(Arc::new(image.clone()));
        Ok(self.images.len() - 1)
    }
}

/// One draw of a scene before anything is on the GPU: which primitive of which instance, with
/// which material, and its `Draw` uniform.
#[derive(Debug, Clone, PartialEq)]
#[cfg(any(test, feature = "internals"))]
pub struct PlannedDraw {
    pub instance: usize,
    pub mesh: usize,
    pub primitive: usize,
    pub material: usize,
    pub uniform: forward::Draw,
    pub local_bounds: Aabb,
}

/// Every draw of `scene`, in instance then primitive order; primitives without a material use
/// the glTF default material, which the renderer adds after the scene's own. Instances naming no mesh draw nothing ([`Scene::check_for_device`]
/// reports them).
#[cfg(any(test, feature = "internals"))]
pub fn draw_plan(scene: &Scene) -> Vec<PlannedDraw> {
    let default_material = scene.materials.len();
    let mut draws = Vec::new();
    for (instance_index, instance) in scene.instances.iter().enumerate() {
        let Some(mesh) = scene.meshes.get(instance.mesh) else {
            continue;
        };
        let world = instance.world_from_mesh;
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let material = primitive.material.unwrap_or(default_material);
            draws.push(PlannedDraw {
                instance: instance_index,
                mesh: instance.mesh,
                primitive: p,
                material,
                uniform: draw_uniform(world, material),
                local_bounds: primitive.bounds,
            });
        }
    }
    draws
}
