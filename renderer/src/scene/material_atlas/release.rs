//! Giving back what the atlas holds for textures no material samples any more: their texture
//! records, and the levels no texture still held shares (their rectangles in the pages and
//! their level records), so that later additions take that room instead of growing the atlas.

use std::collections::HashSet;

use super::levels::{LevelsKey, levels_key};
use super::{AtlasKey, MaterialAtlas};

impl MaterialAtlas {
    /// Releases every texture held that `in_use` does not name: its index may be given to a
    /// texture added later, and its levels' room is reused once no texture held shares them.
    /// Returns how many textures were released. Pages are not taken away (the texture keeps its
    /// layers), and nothing is written to the GPU: nothing samples what was released.
    pub fn release(&mut self, in_use: &HashSet<AtlasKey>) -> usize {
        let released: Vec<AtlasKey> = (self.indices.keys())
            .filter(|key| !in_use.contains(key))
            .copied()
            .collect();
        for key in &released {
            if let Some(index) = self.indices.remove(key) {
                self.free_textures.push(index);
            }
        }
        if released.is_empty() {
            return 0;
        }
        let shared: HashSet<LevelsKey> = self.indices.keys().map(levels_key).collect();
        let unshared: Vec<LevelsKey> = (self.sets.keys())
            .filter(|set| !shared.contains(set))
            .copied()
            .collect();
        for set in unshared {
            let Some(stored) = self.sets.remove(&set) else {
                continue;
            };
            for (layer, allocation) in stored.rectangles {
                if let Some(page) = self.pages.0.get_mut(layer as usize) {
                    page.deallocate(allocation);
                }
            }
            let first = u64::from(stored.first_level);
            self.level_space
                .give_back(first..first + u64::from(stored.levels));
        }
        released.len()
    }

    /// The first of `count` consecutive level records to write a new set into: records given
    /// back where a run is long enough, else new ones past the end.
    pub(super) fn take_level_records(&mut self, count: usize) -> u32 {
        let count = count as u64;
        let range = loop {
            if let Some(range) = self.level_space.take(count) {
                break range;
            }
            let room = self.level_space.capacity();
            self.level_space.grow_to(room + count);
        };
        let end = self.level_space.capacity() as usize;
        if self.level_records.len() < end {
            self.level_records.resize(end, bytemuck::Zeroable::zeroed());
        }
        range.start as u32
    }

    /// Textures held, and the pages' room taken by their levels (texels, borders included).
    pub fn usage(&self) -> (usize, u64) {
        let taken = (self.pages.0.iter())
            .map(|page| page.allocated_space().max(0) as u64)
            .sum();
        (self.indices.len(), taken)
    }
}
