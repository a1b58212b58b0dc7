//! Moving scene instances: which instances are dynamic (shadow casters drawn over the static
//! cache every frame) and where they are.

use std::sync::Arc;

use glam::Mat4;

use super::Renderer;
use crate::frame_data::{InstanceState, RenderError};

impl Renderer {
    /// The instances of the prepared scene (nodes with a mesh, in `Scene::instances` order).
    pub fn instances(&self) -> &[InstanceState] {
        &self.instances
    }

    /// Marks instance `index` dynamic (its shadows are redrawn over the static cache each frame
    /// they can change) or static (cached with the scene). Instances start static.
    pub fn set_instance_dynamic(&mut self, index: usize, dynamic: bool) -> Result<(), RenderError> {
        let state = self.instance_mut(index)?;
        if state.dynamic != dynamic {
            state.dynamic = dynamic;
            state.version += 1;
        }
        Ok(())
    }

    /// Moves instance `index` to `world_from_mesh`, from the next frame. Moving a static
    /// instance invalidates the cached shadows of every light it can reach; mark instances that
    /// move often dynamic.
    pub fn set_instance_transform(
        &mut self,
        index: usize,
        world_from_mesh: Mat4,
    ) -> Result<(), RenderError> {
        let state = self.instance_mut(index)?;
        if state.world_from_mesh == world_from_mesh {
            return Ok(());
        }
        state.world_from_mesh = world_from_mesh;
        state.version += 1;
        if let Some(scene) = &self.scene {
            let stride = size_of::<shaders_gen::forward::forward::Draw>() as u64;
            for d in scene.draws_of_instance(index) {
                let record = scene.draws[d].uniform(world_from_mesh);
                let at = d as u64 * stride;
                let bytes = bytemuck::bytes_of(&record);
                self.gpu.queue.write_buffer(&scene.draw_records, at, bytes);
            }
        }
        Ok(())
    }

    fn instance_mut(&mut self, index: usize) -> Result<&mut InstanceState, RenderError> {
        let count = self.instances.len();
        Arc::make_mut(&mut self.instances)
            .get_mut(index)
            .ok_or(RenderError::NoSuchInstance { index, count })
    }
}
