//! The shadow casters' slots on the GPU: one per draw that casts (opaque draws first, then
//! alpha-masked ones, each part with spare slots for draws an engine adds), the geometry each
//! slot draws, and the box `shadow_cull` tests for each draw.

use shaders_gen::shadow::shadow_cull::{CasterSlot, DrawBox, NO_DRAW};

use crate::frame_data::{InstanceTable, PreparedScene};
use crate::scene::AlphaMode;
use crate::shadow::cache::Caster;

/// The casters' slots: opaque casters, then alpha-masked ones, each part with spare slots.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SlotLayout {
    /// Draws in slot order (`NO_DRAW` in spare slots).
    pub draws: Vec<u32>,
    /// Slots of the opaque part (the masked part follows).
    pub opaque: u32,
    /// Per part (opaque, masked), its first spare slot: spares stay together at each part's
    /// end, since a removed instance keeps its slots (its box is empty).
    free: [usize; 2],
}

impl SlotLayout {
    /// The casters of `table`'s draws: blended draws cast nothing and get no slot.
    pub fn new(scene: &PreparedScene, table: &InstanceTable) -> Self {
        let (mut opaque, mut masked) = (Vec::new(), Vec::new());
        for d in 0..table.draws.len() {
            match caster_kind(scene, table, d) {
                Some(false) => opaque.push(d as u32),
                Some(true) => masked.push(d as u32),
                None => {}
            }
        }
        let free = [opaque.len(), masked.len()];
        let spare = |part: &mut Vec<u32>| part.resize(part.len() + part.len() / 8 + 8, NO_DRAW);
        spare(&mut opaque);
        spare(&mut masked);
        let opaque_slots = opaque.len();
        opaque.extend(masked);
        Self {
            draws: opaque,
            opaque: opaque_slots as u32,
            free: [free[0], opaque_slots + free[1]],
        }
    }

    /// Slots per work item.
    pub fn stride(&self) -> u32 {
        self.draws.len() as u32
    }

    /// Puts draw `d` into a spare slot of its part; `None` when the part is full.
    pub fn place(&mut self, d: u32, masked: bool) -> Option<usize> {
        let part = usize::from(masked);
        let end = [self.opaque as usize, self.draws.len()][part];
        let slot = self.free[part];
        if slot == end {
            return None;
        }
        self.draws[slot] = d;
        self.free[part] += 1;
        Some(slot)
    }
}

/// `Some(masked)` for a draw that casts, `None` for a blended one.
pub fn caster_kind(scene: &PreparedScene, table: &InstanceTable, d: usize) -> Option<bool> {
    let material = scene.materials.get(table.draws[d].material)?;
    match material.alpha_mode {
        AlphaMode::Blend => None,
        AlphaMode::Mask { .. } => Some(true),
        AlphaMode::Opaque => Some(false),
    }
}

pub fn slot_record(table: &InstanceTable, d: u32) -> CasterSlot {
    match table.draws.get(d as usize) {
        Some(draw) if d != NO_DRAW => {
            let g = draw.geometry;
            CasterSlot::new(g.index_count, g.first_index, g.base_vertex as u32, d)
        }
        _ => CasterSlot::new(0, 0, 0, NO_DRAW),
    }
}

/// A caster's box for the GPU: empty (`min > max`) where it casts nothing, `min.w` 1 for a
/// dynamic instance.
pub fn caster_box(c: &Caster) -> DrawBox {
    if c.bounds.is_empty() {
        return DrawBox::new(glam::Vec4::ONE, glam::Vec4::ZERO);
    }
    let dynamic = if c.dynamic { 1.0 } else { 0.0 };
    DrawBox::new(c.bounds.min.extend(dynamic), c.bounds.max.extend(0.0))
}
