//! Editing the shown scene by handle while it runs: `I` adds a hundred instances (copies of the
//! scene's own meshes, each scaled to about a metre) on a grid ahead of the camera, `U` removes
//! the newest hundred. The renderer is not rebuilt, and a settings key reconfigures it in place,
//! so they stay.

use anyhow::Result;
use glam::{Mat4, Quat, Vec3};
use renderer::frame::{InstanceHandle, Renderer};

use crate::fly::Fly;
use crate::scene::Shown;

/// Instances one key press adds or removes.
pub const BATCH: usize = 100;

/// The instances added so far, in order, and their handles in the running renderer.
#[derive(Debug, Default)]
pub struct Added {
    placed: Vec<(usize, Mat4)>,
    handles: Vec<InstanceHandle>,
}

impl Added {
    /// How many are in the scene.
    pub fn count(&self) -> usize {
        self.placed.len()
    }

    /// A hundred instances of `shown`'s meshes on a grid ahead of `fly`, each turned by its
    /// place in the grid.
    pub fn add_batch(&mut self, renderer: &mut Renderer, shown: &Shown, fly: &Fly) -> Result<()> {
        let instances = &shown.scene.instances;
        if instances.is_empty() {
            return Ok(());
        }
        let forward = fly.forward();
        let flat = Vec3::new(forward.x, 0.0, forward.z).normalize_or(Vec3::NEG_Z);
        let side = flat.cross(Vec3::Y);
        let start = self.count();
        for k in start..start + BATCH {
            let source = &instances[(k * 7919) % instances.len()];
            let bounds = shown.scene.meshes[source.mesh]
                .primitives
                .iter()
                .fold(renderer::scene::Aabb::EMPTY, |b, p| b.union(p.bounds));
            let size = (bounds.max - bounds.min).max_element().max(1e-3);
            let (row, column) = ((k / 10) as f32, (k % 10) as f32 - 4.5);
            let at = fly.eye + flat * (4.0 + 1.5 * row) + side * (1.5 * column);
            let world = Mat4::from_scale_rotation_translation(
                Vec3::splat(1.0 / size),
                Quat::from_rotation_y(k as f32 * 0.7),
                at,
            ) * Mat4::from_translation(-bounds.center());
            let handle = renderer.add_instance(source.mesh, world)?;
            self.placed.push((source.mesh, world));
            self.handles.push(handle);
        }
        Ok(())
    }

    /// Removes the newest hundred added instances.
    pub fn remove_batch(&mut self, renderer: &mut Renderer) -> Result<()> {
        for _ in 0..BATCH {
            let (Some(handle), Some(_)) = (self.handles.pop(), self.placed.pop()) else {
                break;
            };
            renderer.remove_instance(handle)?;
        }
        Ok(())
    }
}
