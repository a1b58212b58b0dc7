//! The scene's shadow casters as the shadow pass keeps them across frames: one per draw of the
//! instance table (a blended draw or a removed instance's with empty bounds, reaching no
//! region), so a caster's index is its draw's. When instances change, only their draws'
//! casters are written again, found through the table's change log, and the planner is told
//! which ones ([`CasterChanges::Only`]); a frame where a dynamic instance moves then costs what
//! it touched, not what the scene holds.

use crate::frame_data::{FrameInputs, InstanceTable, PreparedScene};
use crate::scene::{Aabb, AlphaMode};
use crate::shadow::cache::Caster;

/// The casters of a scene's instance table at one of its revisions.
#[derive(Debug)]
pub(super) struct CasterCache {
    /// The scene (id and placement revision: blended materials cast nothing) and instance
    /// table they follow.
    scene: (u32, u64),
    table: u32,
    revision: u64,
    pub casters: Vec<Caster>,
    /// Every caster's bounds together.
    pub bounds: Aabb,
}

impl CasterCache {
    /// The casters of `frame`'s scene, built afresh.
    pub fn new(frame: &FrameInputs) -> Self {
        let table = &frame.instances;
        let casters: Vec<Caster> = (0..table.draws.len())
            .map(|d| caster(&frame.scene, table, d))
            .collect();
        Self {
            scene: scene_key(&frame.scene),
            table: table.id(),
            revision: table.revision,
            bounds: union(&casters),
            casters,
        }
    }

    /// Brings the casters to `frame`'s instances: `Some(changed)` with the casters written
    /// again (ascending) when only those changed since the last call, `None` when they were
    /// built afresh (another scene, or more changes than the log keeps).
    pub fn follow(&mut self, frame: &FrameInputs) -> Option<Vec<u32>> {
        let table = &frame.instances;
        if self.scene != scene_key(&frame.scene) || self.table != table.id() {
            *self = Self::new(frame);
            return None;
        }
        if self.revision == table.revision {
            return Some(Vec::new());
        }
        let Some(instances) = table.changed_since(self.revision) else {
            *self = Self::new(frame);
            return None;
        };
        let mut changed = Vec::new();
        let mut shrinks = false;
        for state in instances.iter().filter_map(|&i| table.states.get(i)) {
            for d in state.draws() {
                let new = caster(&frame.scene, table, d);
                match self.casters.get_mut(d) {
                    Some(old) => {
                        // Bounds can only shrink where an old box reached their edge.
                        shrinks |= touches_edge(old.bounds, self.bounds);
                        *old = new;
                    }
                    None => {
                        let placeholder = Caster {
                            bounds: Aabb::EMPTY,
                            ..new
                        };
                        self.casters.resize(d, placeholder);
                        self.casters.push(new);
                    }
                }
                self.bounds = self.bounds.union(new.bounds);
                changed.push(d as u32);
            }
        }
        if shrinks {
            self.bounds = union(&self.casters);
        }
        self.revision = table.revision;
        changed.sort_unstable();
        Some(changed)
    }
}

fn scene_key(scene: &PreparedScene) -> (u32, u64) {
    (scene.id, scene.placement_revision)
}

/// The caster of draw `d`: where its instance is now, or empty bounds when it casts nothing
/// (blended, or its instance removed).
fn caster(scene: &PreparedScene, table: &InstanceTable, d: usize) -> Caster {
    let draw = &table.draws[d];
    let state = table.states.get(draw.instance);
    let blended = scene
        .materials
        .get(draw.material)
        .is_none_or(|m| m.alpha_mode == AlphaMode::Blend);
    Caster {
        draw: d as u32,
        bounds: if blended {
            Aabb::EMPTY
        } else {
            draw.world_bounds(&table.states)
        },
        dynamic: state.is_some_and(|s| s.dynamic),
        version: state.map_or(0, |s| s.version),
    }
}

fn union(casters: &[Caster]) -> Aabb {
    casters.iter().fold(Aabb::EMPTY, |b, c| b.union(c.bounds))
}

/// Whether `b` (not empty) reaches a face of `bounds`.
fn touches_edge(b: Aabb, bounds: Aabb) -> bool {
    !b.is_empty() && (b.min.cmple(bounds.min).any() || b.max.cmpge(bounds.max).any())
}
