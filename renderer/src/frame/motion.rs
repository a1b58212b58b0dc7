//! Editing the scene's instances between frames, by handle: add an instance of a mesh, remove
//! one, move one, mark one dynamic (its shadows drawn over the static cache each frame), give
//! one of its primitives another material.
//!
//! Each edit writes what it changes to the GPU (the instance's draw records) and nothing else;
//! the passes follow on the next frame from the instances whose version moved
//! ([`crate::frame_data::InstanceTable`]).

use crate::frame_data::InputError;
use std::sync::Arc;

use glam::Mat4;

use super::Renderer;
use crate::frame_data::{
    InstanceEditError, InstanceHandle, InstanceState, InstanceTable, RenderError,
};

impl Renderer {
    /// The instance slots of the prepared scene: its nodes with a mesh in `Scene::instances`
    /// order, then the slots of added instances. A removed instance's slot stays, with
    /// `live` false, until an instance of the same mesh is added.
    pub fn instances(&self) -> &[InstanceState] {
        self.scene.as_ref().map_or(&[], |(_, table)| &table.states)
    }

    /// The handle of the prepared scene's instance `index` (`Scene::instances` order), while
    /// it is in the scene (an instance added into its slot after it was removed is not it).
    pub fn scene_instance(&self, index: usize) -> Result<InstanceHandle, RenderError> {
        let table = self.table()?;
        table
            .scene_handle(index)
            .ok_or(RenderError::Input(InputError::NoSuchInstance {
                index,
                count: table.states.len(),
            }))
    }

    /// The instance `handle` names, if it is still in the scene.
    pub fn instance(&self, handle: InstanceHandle) -> Option<&InstanceState> {
        self.scene.as_ref()?.1.get(handle)
    }

    /// Adds an instance of the prepared scene's mesh `mesh` at `world_from_mesh`, static,
    /// from the next frame. It takes the slot and draws of a removed instance of the same mesh
    /// where there is one; nothing else is uploaded again.
    pub fn add_instance(
        &mut self,
        mesh: usize,
        world_from_mesh: Mat4,
    ) -> Result<InstanceHandle, RenderError> {
        let gpu = self.gpu.clone();
        let (prepared, table) = self
            .scene
            .as_mut()
            .ok_or(RenderError::Input(InputError::NoScene))?;
        let table = Arc::make_mut(table);
        table
            .add(&gpu, prepared, mesh, world_from_mesh, false)
            .map_err(|e| edit_error(e, 0))
    }

    /// Removes `handle`'s instance from the next frame; the handle is refused from now on.
    pub fn remove_instance(&mut self, handle: InstanceHandle) -> Result<(), RenderError> {
        self.table_mut()?
            .remove(handle)
            .map_err(|e| edit_error(e, handle.index()))
    }

    /// Marks `handle`'s instance dynamic (its shadows are redrawn over the static cache each
    /// frame they can change) or static (cached with the scene). Instances start static.
    pub fn set_instance_dynamic(
        &mut self,
        handle: InstanceHandle,
        dynamic: bool,
    ) -> Result<(), RenderError> {
        self.table_mut()?
            .set_dynamic(handle, dynamic)
            .map_err(|e| edit_error(e, handle.index()))
    }

    /// Moves `handle`'s instance to `world_from_mesh`, from the next frame. Moving a static
    /// instance invalidates the cached shadows of every light it can reach; mark instances that
    /// move often dynamic.
    pub fn set_instance_transform(
        &mut self,
        handle: InstanceHandle,
        world_from_mesh: Mat4,
    ) -> Result<(), RenderError> {
        let gpu = self.gpu.clone();
        self.table_mut()?
            .set_transform(&gpu, handle, world_from_mesh)
            .map_err(|e| edit_error(e, handle.index()))
    }

    /// Draws primitive `primitive` of `handle`'s instance with material `material` of the
    /// prepared scene from the next frame, instead of its mesh's: instances of one mesh can
    /// differ in material (any material, glTF's or one of a material program). Only that
    /// draw's record is written; a change of batch (alpha mode, sidedness, program) moves that
    /// draw alone. A new instance of the mesh takes the mesh's materials again. An unknown or
    /// removed material is [`InputError::Scene`](crate::frame::InputError::Scene), a primitive past the mesh's
    /// [`InputError::NoSuchPrimitive`](crate::frame::InputError::NoSuchPrimitive).
    pub fn set_instance_material(
        &mut self,
        handle: InstanceHandle,
        primitive: usize,
        material: usize,
    ) -> Result<(), RenderError> {
        let gpu = self.gpu.clone();
        let (prepared, table) = self
            .scene
            .as_mut()
            .ok_or(RenderError::Input(InputError::NoScene))?;
        prepared.check_material_index(material)?;
        Arc::make_mut(table)
            .set_material(&gpu, handle, primitive, material)
            .map_err(|e| edit_error(e, handle.index()))
    }

    fn table(&self) -> Result<&InstanceTable, RenderError> {
        self.scene
            .as_ref()
            .map(|(_, t)| t.as_ref())
            .ok_or(RenderError::Input(InputError::NoScene))
    }

    fn table_mut(&mut self) -> Result<&mut InstanceTable, RenderError> {
        let (_, table) = self
            .scene
            .as_mut()
            .ok_or(RenderError::Input(InputError::NoScene))?;
        Ok(Arc::make_mut(table))
    }
}

fn edit_error(e: InstanceEditError, index: usize) -> RenderError {
    match e {
        InstanceEditError::Stale => RenderError::Input(InputError::StaleInstance { index }),
        InstanceEditError::NoSuchMesh { mesh, count } => {
            RenderError::Input(InputError::NoSuchMesh { mesh, count })
        }
        InstanceEditError::MeshRemoved { mesh } => {
            RenderError::Input(InputError::MeshRemoved { mesh })
        }
        InstanceEditError::NotFinite => RenderError::Input(InputError::NotFiniteTransform),
        InstanceEditError::NoSuchPrimitive { primitive, count } => {
            RenderError::Input(InputError::NoSuchPrimitive { primitive, count })
        }
    }
}
