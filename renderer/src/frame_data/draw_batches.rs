//! How the geometry passes draw a prepared scene: its opaque and masked draws laid out in
//! slots, grouped into batches that share a pipeline and a material (one multi-draw each), and
//! its blended draws apart (sorted back to front every frame).
//!
//! The layout is GPU-free; `passes::scene_cull` uploads it as indirect arguments and culls the
//! slots on the GPU. Every path draws the same batches in the same order, culled or not, so
//! culling changes which draws run and nothing else.

use super::scene::{InstanceState, PreparedScene};
use crate::scene::AlphaMode;

/// Draws that share a pipeline and a material, in consecutive slots.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DrawBatch {
    pub material: usize,
    /// Alpha-masked (the masked depth pipelines and the material's mask group).
    pub masked: bool,
    pub double_sided: bool,
    /// Mirrored by its instances' transforms (the clockwise pipelines).
    pub mirrored: bool,
    /// Its slots.
    pub first_slot: u32,
    pub slot_count: u32,
}

impl DrawBatch {
    /// What its draws share.
    pub fn key(&self) -> BatchKey {
        (self.masked, self.double_sided, self.mirrored, self.material)
    }

    /// Its slots' range.
    pub fn slots(&self) -> std::ops::Range<u32> {
        self.first_slot..self.first_slot + self.slot_count
    }
}

/// A scene's draws as the geometry passes draw them.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct BatchLayout {
    /// Opaque and masked batches, ordered by (masked, double-sided, mirrored, material).
    pub batches: Vec<DrawBatch>,
    /// The draw (index into `PreparedScene::draws`) of each slot; ascending within a batch.
    pub slot_draws: Vec<u32>,
    /// The blended draws, in scene order (`passes::forward` sorts them each frame).
    pub blended: Vec<u32>,
}

/// What puts a draw in a batch: (masked, double-sided, mirrored, material).
pub type BatchKey = (bool, bool, bool, usize);

impl BatchLayout {
    /// The layout of `scene` with its instances where `instances` put them (mirroring picks the
    /// pipeline, so a move that mirrors or unmirrors an instance calls for a new layout).
    pub fn new(scene: &PreparedScene, instances: &[InstanceState]) -> Self {
        Self::from_keys(scene.draws.iter().map(|draw| {
            let material = &scene.materials[draw.material];
            let masked = match material.alpha_mode {
                AlphaMode::Blend => return None,
                AlphaMode::Mask { .. } => material.prez_mask_group.is_some(),
                AlphaMode::Opaque => false,
            };
            Some((
                masked,
                material.double_sided,
                draw.mirrored(instances),
                draw.material,
            ))
        }))
    }

    /// The layout of draws `0..` with these batch keys (`None`: blended).
    pub fn from_keys(keys: impl Iterator<Item = Option<BatchKey>>) -> Self {
        let mut keyed = Vec::new();
        let mut blended = Vec::new();
        for (d, key) in keys.enumerate() {
            match key {
                Some(key) => keyed.push((key, d as u32)),
                None => blended.push(d as u32),
            }
        }
        // Stable: draws keep their scene order within a batch.
        keyed.sort_by_key(|&(key, _)| key);
        let mut batches: Vec<DrawBatch> = Vec::new();
        for (slot, &((masked, double_sided, mirrored, material), _)) in keyed.iter().enumerate() {
            match batches.last_mut() {
                Some(b) if b.key() == (masked, double_sided, mirrored, material) => {
                    b.slot_count += 1;
                }
                _ => batches.push(DrawBatch {
                    material,
                    masked,
                    double_sided,
                    mirrored,
                    first_slot: slot as u32,
                    slot_count: 1,
                }),
            }
        }
        Self {
            batches,
            slot_draws: keyed.into_iter().map(|(_, d)| d).collect(),
            blended,
        }
    }

    /// Slots in all batches.
    pub fn slot_count(&self) -> u32 {
        self.slot_draws.len() as u32
    }
}

/// Whether some instance is mirrored in `after` and not in `before` or the other way round (a
/// scene's batch layout must then be rebuilt).
pub fn mirroring_changed(before: &[InstanceState], after: &[InstanceState]) -> bool {
    before.len() != after.len()
        || before
            .iter()
            .zip(after)
            .any(|(b, a)| b.mirrored() != a.mirrored())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn batches_group_by_pipeline_then_material_and_keep_scene_order_inside() {
        let opaque = |m| Some((false, false, false, m));
        let keys = [
            opaque(2),
            None,
            Some((true, true, false, 1)),
            opaque(0),
            opaque(2),
            Some((false, false, true, 0)),
            None,
            opaque(0),
        ];
        let layout = BatchLayout::from_keys(keys.into_iter());
        let batches: Vec<(BatchKey, u32, u32)> = layout
            .batches
            .iter()
            .map(|b| (b.key(), b.first_slot, b.slot_count))
            .collect();
        assert_eq!(
            batches,
            [
                ((false, false, false, 0), 0, 2),
                ((false, false, false, 2), 2, 2),
                ((false, false, true, 0), 4, 1),
                ((true, true, false, 1), 5, 1),
            ]
        );
        assert_eq!(layout.slot_draws, [3, 7, 0, 4, 5, 2]);
        assert_eq!(layout.blended, [1, 6]);
        assert_eq!(layout.slot_count(), 6);
    }
}
