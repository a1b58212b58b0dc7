//! How the geometry passes draw a prepared scene: its opaque and masked draws laid out in
//! slots, grouped into batches that share a pipeline (one multi-draw each: every material is
//! reached through the draw's record, so materials do not split batches), and
//! its blended draws apart (sorted back to front every frame).
//!
//! The layout is GPU-free; `passes::scene_cull` uploads it as indirect arguments and culls the
//! slots on the GPU. Every path draws the same batches in the same order, culled or not, so
//! culling changes which draws run and nothing else.

use super::instances::InstanceTable;
use super::scene::PreparedScene;
use crate::scene::AlphaMode;

/// A slot that holds no draw (a batch's spare slot, or one whose draw left): its arguments
/// draw nothing.
pub const NO_DRAW: u32 = shaders_gen::culling::instance_cull::NO_DRAW;

/// Draws that share a pipeline, in consecutive slots.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DrawBatch {
    /// Alpha-masked (the masked depth pipelines).
    pub masked: bool,
    pub double_sided: bool,
    /// Mirrored by its instances' transforms (the clockwise pipelines).
    pub mirrored: bool,
    /// Its materials' program: 0 for glTF PBR, else the scene's number of a material program
    /// (`PreparedScene::material_program`), whose pipelines the forward and G-buffer passes
    /// draw it with.
    pub program: u32,
    /// Its slots, spare ones included.
    pub first_slot: u32,
    pub slot_count: u32,
}

impl DrawBatch {
    /// What its draws share.
    pub fn key(&self) -> BatchKey {
        (self.masked, self.double_sided, self.mirrored, self.program)
    }

    /// Its slots' range.
    pub fn slots(&self) -> std::ops::Range<u32> {
        self.first_slot..self.first_slot + self.slot_count
    }
}

/// Where a draw goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DrawPlace {
    /// A slot of the batch with this key.
    Batch(BatchKey),
    /// The blended draws, sorted each frame.
    Blended,
    /// Nowhere: its instance was removed.
    Hidden,
}

/// A scene's draws as the geometry passes draw them.
///
/// Every batch has spare slots (an eighth of its draws, at least two) that hold [`NO_DRAW`],
/// so an instance added to the scene, or one whose mirroring changed, takes a slot in place
/// ([`BatchLayout::place`]); only when its batch is full, or new, is the layout built again.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct BatchLayout {
    /// Opaque and masked batches, ordered by (masked, double-sided, mirrored, program).
    pub batches: Vec<DrawBatch>,
    /// The draw (index into `InstanceTable::draws`) of each slot, or [`NO_DRAW`].
    pub slot_draws: Vec<u32>,
    /// The blended draws, ascending (`passes::forward` sorts them each frame).
    pub blended: Vec<u32>,
    /// Each draw's slot, or [`NO_DRAW`] (blended, hidden).
    slot_of_draw: Vec<u32>,
    /// Each batch's empty slots.
    free_slots: Vec<Vec<u32>>,
}

/// What puts a draw in a batch: (masked, double-sided, mirrored, material program).
pub type BatchKey = (bool, bool, bool, u32);

/// The batch is full or missing: the layout must be built again.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NoRoom;

/// Where draw `d` of `table` goes (mirroring and the material program pick the pipeline, so a
/// move that mirrors or unmirrors an instance moves its draws to another batch).
pub fn draw_place(scene: &PreparedScene, table: &InstanceTable, d: usize) -> DrawPlace {
    let draw = &table.draws[d];
    if !table.states.get(draw.instance).is_some_and(|s| s.live) {
        return DrawPlace::Hidden;
    }
    let material = &scene.materials[draw.material];
    let masked = match material.alpha_mode {
        AlphaMode::Blend => return DrawPlace::Blended,
        AlphaMode::Mask { .. } => true,
        AlphaMode::Opaque => false,
    };
    let program = scene.material_program(draw.material);
    DrawPlace::Batch((
        masked,
        material.double_sided,
        draw.mirrored(&table.states),
        program,
    ))
}

impl BatchLayout {
    /// The layout of `table`'s draws.
    pub fn new(scene: &PreparedScene, table: &InstanceTable) -> Self {
        Self::from_places((0..table.draws.len()).map(|d| draw_place(scene, table, d)))
    }

    /// The layout of draws `0..` placed so.
    pub fn from_places(places: impl Iterator<Item = DrawPlace>) -> Self {
        let mut keyed = Vec::new();
        let mut blended = Vec::new();
        let mut draws = 0;
        for (d, place) in places.enumerate() {
            draws = d + 1;
            match place {
                DrawPlace::Batch(key) => keyed.push((key, d as u32)),
                DrawPlace::Blended => blended.push(d as u32),
                DrawPlace::Hidden => {}
            }
        }
        // Stable: draws keep their scene order within a batch.
        keyed.sort_by_key(|&(key, _)| key);
        let mut layout = Self {
            blended,
            slot_of_draw: vec![NO_DRAW; draws],
            ..Self::default()
        };
        for run in keyed.chunk_by(|a, b| a.0 == b.0) {
            let (masked, double_sided, mirrored, program) = run[0].0;
            let first_slot = layout.slot_draws.len() as u32;
            let spare = run.len() / 8 + 2;
            for &(_, d) in run {
                layout.slot_of_draw[d as usize] = layout.slot_draws.len() as u32;
                layout.slot_draws.push(d);
            }
            let free = (0..spare).map(|i| first_slot + (run.len() + spare - 1 - i) as u32);
            layout.free_slots.push(free.collect());
            layout
                .slot_draws
                .extend(std::iter::repeat_n(NO_DRAW, spare));
            layout.batches.push(DrawBatch {
                masked,
                double_sided,
                mirrored,
                program,
                first_slot,
                slot_count: (run.len() + spare) as u32,
            });
        }
        layout
    }

    /// Slots in all batches, spare ones included.
    pub fn slot_count(&self) -> u32 {
        self.slot_draws.len() as u32
    }

    /// Slots that hold a draw.
    pub fn draw_count(&self) -> u32 {
        let free: usize = self.free_slots.iter().map(Vec::len).sum();
        (self.slot_draws.len() - free) as u32
    }

    /// Draw `d`'s slot, if it has one.
    pub fn slot_of(&self, d: u32) -> Option<u32> {
        self.slot_of_draw
            .get(d as usize)
            .copied()
            .filter(|&s| s != NO_DRAW)
    }

    /// Moves draw `d` to `place`, returning the slots whose draw changed; [`NoRoom`] when its
    /// batch has no spare slot or does not exist (the layout is then unchanged).
    pub fn place(&mut self, d: u32, place: DrawPlace) -> Result<Vec<u32>, NoRoom> {
        let index = d as usize;
        let current = self.slot_of(d).map(|s| self.batch_of_slot(s));
        let blended = self.blended.binary_search(&d);
        match (place, current) {
            (DrawPlace::Batch(key), Some(b)) if self.batches[b].key() == key => {
                return Ok(Vec::new());
            }
            (DrawPlace::Blended, _) if blended.is_ok() => return Ok(Vec::new()),
            (DrawPlace::Hidden, None) if blended.is_err() => return Ok(Vec::new()),
            _ => {}
        }
        let target = match place {
            DrawPlace::Batch(key) => {
                let b = self
                    .batches
                    .binary_search_by_key(&key, DrawBatch::key)
                    .map_err(|_| NoRoom)?;
                Some((b, *self.free_slots[b].last().ok_or(NoRoom)?))
            }
            _ => None,
        };
        if index >= self.slot_of_draw.len() {
            self.slot_of_draw.resize(index + 1, NO_DRAW);
        }
        let mut changed = Vec::new();
        if let Some(b) = current {
            let slot = self.slot_of_draw[index];
            self.slot_draws[slot as usize] = NO_DRAW;
            self.free_slots[b].push(slot);
            self.slot_of_draw[index] = NO_DRAW;
            changed.push(slot);
        }
        if let Ok(at) = blended {
            self.blended.remove(at);
        }
        match (place, target) {
            (DrawPlace::Batch(_), Some((b, slot))) => {
                self.free_slots[b].pop();
                self.slot_draws[slot as usize] = d;
                self.slot_of_draw[index] = slot;
                changed.push(slot);
            }
            (DrawPlace::Blended, _) => {
                let at = self.blended.partition_point(|&x| x < d);
                self.blended.insert(at, d);
            }
            _ => {}
        }
        Ok(changed)
    }

    /// The batch that holds `slot`.
    fn batch_of_slot(&self, slot: u32) -> usize {
        self.batches.partition_point(|b| b.first_slot <= slot) - 1
    }
}

#[cfg(test)]
#[path = "draw_batches_tests.rs"]
mod tests;
