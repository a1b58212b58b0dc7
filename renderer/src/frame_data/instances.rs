//! The scene's instances and their draws as an engine edits them: add, remove, move and mark
//! dynamic by [`InstanceHandle`], each change written to the GPU where it lands and nothing
//! else re-uploaded.
//!
//! An instance draws every primitive of its mesh; its draws are consecutive entries of
//! [`InstanceTable::draws`] and records of the `view` library's `DRAWS` (group 1 of every
//! geometry pass), which the geometry passes index by instance index. A removed instance keeps
//! its slot and its draws, dead (drawn by no pass), until an instance of the same mesh is added
//! and takes them over; only an instance of a mesh with no free slot appends draws. The
//! records buffer grows by doubling, copied on the GPU.
//!
//! Every change bumps [`InstanceTable::revision`] and the instance's
//! [`InstanceState::version`], and logs the instance ([`InstanceTable::changed_since`]);
//! passes keep what they derived (batches, boxes, shadow casters) and, when the revision
//! moved, update it from the instances the log names, so a frame after an edit costs what
//! the edit touched, not what the scene holds.

use std::ops::Range;

use glam::Mat4;
use records::{draw_group, records_buffer};
use shaders_gen::forward::forward;

mod records;

use super::change_log::ChangeLog;
use super::scene::{PreparedScene, is_mirrored};
use crate::GpuContext;
use crate::frame_data::RenderError;
use crate::scene::{Aabb, GpuPrimitive, Scene};

/// An instance of the renderer's scene, as [`crate::frame::Renderer::add_instance`] returned
/// it or [`crate::frame::Renderer::scene_instance`] named it. A handle outlives its instance:
/// once the instance is removed, the handle is refused, even after its slot is reused, and so
/// is a handle of an earlier scene's instance.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct InstanceHandle {
    /// The table (one per prepared scene) that gave it.
    table: u32,
    index: u32,
    generation: u32,
}

impl InstanceHandle {
    /// The instance's slot: its index in [`crate::frame::Renderer::instances`].
    pub fn index(self) -> usize {
        self.index as usize
    }
}

/// One instance: which mesh, where, and whether it moves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InstanceState {
    /// Its mesh, an index into the scene's meshes.
    pub mesh: usize,
    /// World from mesh space.
    pub world_from_mesh: Mat4,
    /// Dynamic instances are drawn over the static shadow cache every frame they can shadow a
    /// region; static ones are cached.
    pub dynamic: bool,
    /// False once removed: its draws are drawn by no pass.
    pub live: bool,
    /// Bumped whenever anything above changes.
    pub version: u64,
    /// Its draws: `first_draw..first_draw + draw_count` of `InstanceTable::draws`.
    pub first_draw: u32,
    /// How many draws: one per primitive of its mesh.
    pub draw_count: u32,
    /// Bumped each time the slot is given to a new instance (handles of older ones fail).
    generation: u32,
}

impl InstanceState {
    /// Whether the instance is mirrored where it is now (`is_mirrored`).
    pub fn mirrored(&self) -> bool {
        is_mirrored(self.world_from_mesh)
    }

    /// Its draws' indices.
    pub fn draws(&self) -> Range<usize> {
        self.first_draw as usize..(self.first_draw + self.draw_count) as usize
    }
}

/// One primitive of one instance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DrawItem {
    /// The instance (index into `InstanceTable::states`) it belongs to.
    pub instance: usize,
    /// Its material, an index into [`super::PreparedScene::materials`].
    pub material: usize,
    /// Where its primitive lies in the scene's shared geometry buffers.
    pub geometry: GpuPrimitive,
    /// The primitive's bounds in mesh space.
    pub local_bounds: Aabb,
}

impl DrawItem {
    /// The record of this draw at `world_from_mesh`.
    pub fn uniform(&self, world_from_mesh: Mat4) -> forward::Draw {
        super::scene::draw_uniform(world_from_mesh, self.material)
    }

    /// Whether the draw is mirrored where its instance is now: a moved instance can become
    /// mirrored or stop being so.
    pub fn mirrored(&self, instances: &[InstanceState]) -> bool {
        instances
            .get(self.instance)
            .is_some_and(InstanceState::mirrored)
    }

    /// Its world bounds where `instances` put its instance; empty when the instance is dead.
    pub fn world_bounds(&self, instances: &[InstanceState]) -> Aabb {
        match instances.get(self.instance) {
            Some(i) if i.live => self.local_bounds.transformed(i.world_from_mesh),
            Some(_) => Aabb::EMPTY,
            None => self.local_bounds,
        }
    }
}

/// The instances, their draws, and the draw records on the GPU.
#[derive(Debug, Clone)]
pub struct InstanceTable {
    pub states: Vec<InstanceState>,
    pub draws: Vec<DrawItem>,
    /// Removed instances by mesh, for reuse.
    free: Vec<Vec<u32>>,
    /// Live instances by mesh.
    live_by_mesh: Vec<u32>,
    /// The `view` library's `DRAWS`: one `Draw` record per draw, `capacity` records long.
    records: wgpu::Buffer,
    capacity: usize,
    /// Group 1 of the pre-Z, forward, G-buffer and shadow-caster programs: `records`.
    pub draw_group: wgpu::BindGroup,
    layout: wgpu::BindGroupLayout,
    /// Bumped by every change.
    pub revision: u64,
    /// The instance each recent change touched.
    log: ChangeLog,
    /// This table's identity in its handles (a new table per prepared scene).
    id: u32,
    /// The instances the scene itself placed (slots `0..scene_instances`).
    scene_instances: usize,
}

/// Why an instance edit was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InstanceEditError {
    /// The handle's instance was removed (or never existed in this scene).
    Stale,
    /// The mesh index is past the scene's meshes.
    NoSuchMesh { mesh: usize, count: usize },
    /// The mesh was removed.
    MeshRemoved { mesh: usize },
    /// The transform has a NaN or an infinity.
    NotFinite,
    /// The primitive index is past the instance's mesh's primitives.
    NoSuchPrimitive { primitive: usize, count: usize },
}

impl InstanceTable {
    /// The instances of `scene` where the file placed them, static, its draws' records on the
    /// GPU with room for a quarter more.
    pub fn new(
        gpu: &GpuContext,
        prepared: &PreparedScene,
        scene: &Scene,
    ) -> Result<Self, RenderError> {
        let draws: usize = (scene.instances.iter())
            .map(|i| prepared.mesh_draws.get(i.mesh).map_or(0, Vec::len))
            .sum();
        let mut table = Self::empty(gpu, prepared, draws + draws / 4 + 16)?;
        for instance in &scene.instances {
            table.push(prepared, instance.mesh, instance.world_from_mesh, false);
        }
        table.scene_instances = table.states.len();
        table.write_records(gpu, 0..table.draws.len());
        table.revision = 0;
        Ok(table)
    }

    fn empty(
        gpu: &GpuContext,
        prepared: &PreparedScene,
        capacity: usize,
    ) -> Result<Self, RenderError> {
        static NEXT_ID: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(1);
        let layout = prepared.draw_layout().clone();
        let records = records_buffer(gpu.device(), capacity);
        let draw_group = draw_group(gpu.device(), &layout, &records)?;
        Ok(Self {
            states: Vec::new(),
            draws: Vec::new(),
            free: vec![Vec::new(); prepared.mesh_draws.len()],
            live_by_mesh: vec![0; prepared.mesh_draws.len()],
            records,
            capacity: capacity.max(1),
            draw_group,
            layout,
            revision: 0,
            log: ChangeLog::default(),
            id: NEXT_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            scene_instances: 0,
        })
    }

    /// The handle of the live instance in slot `index`.
    pub fn handle(&self, index: usize) -> Option<InstanceHandle> {
        let s = self.states.get(index).filter(|s| s.live)?;
        Some(InstanceHandle {
            table: self.id,
            index: index as u32,
            generation: s.generation,
        })
    }

    /// The handle of the scene's own instance `index` (`Scene::instances` order), while it is
    /// in the scene: not that of an added instance that took its slot after it was removed.
    pub fn scene_handle(&self, index: usize) -> Option<InstanceHandle> {
        self.handle(index)
            .filter(|h| index < self.scene_instances && h.generation == 0)
    }

    /// The live instance `handle` names.
    pub fn get(&self, handle: InstanceHandle) -> Option<&InstanceState> {
        self.states
            .get(handle.index())
            .filter(|s| handle.table == self.id && s.live && s.generation == handle.generation)
    }

    /// Adds an instance of `mesh` at `world_from_mesh`: into the slot of a removed instance of
    /// the same mesh if there is one (its draws reused), else appended with new draws.
    pub fn add(
        &mut self,
        gpu: &GpuContext,
        prepared: &PreparedScene,
        mesh: usize,
        world_from_mesh: Mat4,
        dynamic: bool,
    ) -> Result<InstanceHandle, InstanceEditError> {
        let count = prepared.mesh_draws.len();
        if mesh >= count {
            return Err(InstanceEditError::NoSuchMesh { mesh, count });
        }
        if prepared.mesh_removed(mesh) {
            return Err(InstanceEditError::MeshRemoved { mesh });
        }
        check_finite(world_from_mesh)?;
        if self.free.len() < count {
            self.free.resize(count, Vec::new());
        }
        if self.live_by_mesh.len() < count {
            self.live_by_mesh.resize(count, 0);
        }
        let index = match self.free[mesh].pop() {
            Some(index) => {
                // The mesh's materials, whatever the removed instance drew with.
                let templates = &prepared.mesh_draws[mesh];
                let draws = self.states[index as usize].draws();
                for (d, t) in self.draws[draws].iter_mut().zip(templates) {
                    d.material = t.material;
                }
                let s = &mut self.states[index as usize];
                s.world_from_mesh = world_from_mesh;
                s.dynamic = dynamic;
                s.live = true;
                s.version += 1;
                s.generation += 1;
                self.live_by_mesh[mesh] += 1;
                index as usize
            }
            None => {
                let needed = self.draws.len() + prepared.mesh_draws[mesh].len();
                if needed > self.capacity {
                    self.grow_records(gpu, needed.max(2 * self.capacity));
                }
                self.push(prepared, mesh, world_from_mesh, dynamic)
            }
        };
        self.write_records(gpu, self.states[index].draws());
        self.bump(index);
        self.handle(index).ok_or(InstanceEditError::Stale)
    }

    /// How many live instances use mesh `mesh`.
    pub fn instances_of(&self, mesh: usize) -> usize {
        self.live_by_mesh.get(mesh).map_or(0, |&n| n as usize)
    }

    /// Removes `handle`'s instance: its draws stop drawing, its slot waits for the next
    /// instance of its mesh.
    pub fn remove(&mut self, handle: InstanceHandle) -> Result<(), InstanceEditError> {
        let state = self.live_mut(handle)?;
        state.live = false;
        state.version += 1;
        let mesh = state.mesh;
        if let Some(free) = self.free.get_mut(mesh) {
            free.push(handle.index);
        }
        if let Some(live) = self.live_by_mesh.get_mut(mesh) {
            *live -= 1;
        }
        self.bump(handle.index());
        Ok(())
    }

    /// Moves `handle`'s instance, rewriting its draws' records.
    pub fn set_transform(
        &mut self,
        gpu: &GpuContext,
        handle: InstanceHandle,
        world_from_mesh: Mat4,
    ) -> Result<(), InstanceEditError> {
        check_finite(world_from_mesh)?;
        let state = self.live_mut(handle)?;
        if state.world_from_mesh == world_from_mesh {
            return Ok(());
        }
        state.world_from_mesh = world_from_mesh;
        state.version += 1;
        let draws = state.draws();
        self.write_records(gpu, draws);
        self.bump(handle.index());
        Ok(())
    }

    /// Draws primitive `primitive` of `handle`'s instance with material `material` (checked by
    /// the caller), rewriting that draw's record; the passes place it again from the log.
    pub fn set_material(
        &mut self,
        gpu: &GpuContext,
        handle: InstanceHandle,
        primitive: usize,
        material: usize,
    ) -> Result<(), InstanceEditError> {
        let state = self.live_mut(handle)?;
        let count = state.draw_count as usize;
        if primitive >= count {
            return Err(InstanceEditError::NoSuchPrimitive { primitive, count });
        }
        let d = state.first_draw as usize + primitive;
        state.version += 1;
        self.draws[d].material = material;
        self.write_records(gpu, d..d + 1);
        self.bump(handle.index());
        Ok(())
    }

    /// Marks `handle`'s instance dynamic or static.
    pub fn set_dynamic(
        &mut self,
        handle: InstanceHandle,
        dynamic: bool,
    ) -> Result<(), InstanceEditError> {
        let state = self.live_mut(handle)?;
        if state.dynamic != dynamic {
            state.dynamic = dynamic;
            state.version += 1;
            self.bump(handle.index());
        }
        Ok(())
    }

    /// The instances changed since `revision` (ascending, each once), or `None` when the log
    /// no longer reaches back that far: the caller then looks at every instance.
    pub fn changed_since(&self, revision: u64) -> Option<Vec<usize>> {
        let mut changed: Vec<usize> = self
            .log
            .since(revision)?
            .iter()
            .map(|&i| i as usize)
            .collect();
        changed.sort_unstable();
        changed.dedup();
        Some(changed)
    }

    /// Records a change of instance `index`: a new revision, logged.
    fn bump(&mut self, index: usize) {
        self.log.record(index as u32);
        self.revision += 1;
    }

    /// This table's identity: a pass that followed another table (an earlier scene's) starts
    /// again.
    pub fn id(&self) -> u32 {
        self.id
    }

    fn live_mut(
        &mut self,
        handle: InstanceHandle,
    ) -> Result<&mut InstanceState, InstanceEditError> {
        self.states
            .get_mut(handle.index())
            .filter(|s| handle.table == self.id && s.live && s.generation == handle.generation)
            .ok_or(InstanceEditError::Stale)
    }

    /// Appends an instance and its draws (the records are not written).
    fn push(
        &mut self,
        prepared: &PreparedScene,
        mesh: usize,
        world_from_mesh: Mat4,
        dynamic: bool,
    ) -> usize {
        let index = self.states.len();
        let templates = prepared.mesh_draws.get(mesh).map_or(&[][..], Vec::as_slice);
        if let Some(live) = self.live_by_mesh.get_mut(mesh) {
            *live += 1;
        }
        self.states.push(InstanceState {
            mesh,
            world_from_mesh,
            dynamic,
            live: true,
            version: 0,
            first_draw: self.draws.len() as u32,
            draw_count: templates.len() as u32,
            generation: 0,
        });
        self.draws.extend(templates.iter().map(|t| DrawItem {
            instance: index,
            material: t.material,
            geometry: t.geometry,
            local_bounds: t.local_bounds,
        }));
        index
    }
}

fn check_finite(m: Mat4) -> Result<(), InstanceEditError> {
    if m.is_finite() {
        Ok(())
    } else {
        Err(InstanceEditError::NotFinite)
    }
}
