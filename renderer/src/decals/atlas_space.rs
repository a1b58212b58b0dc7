//! Room in a packed decal atlas, kept so that a later set of decals can add and remove
//! materials in place: a removed material's rectangle is given back, and a new material is
//! allocated in free room and its levels built for its rectangle alone.
//!
//! Allocations are aligned to, and sized in multiples of, the gutter `2^(L−1)`, so each level
//! of a rectangle is a whole rectangle of that level and its 2×2 box filter reads only the
//! rectangle's own texels one level up: a rectangle's levels built on their own equal the
//! levels of the whole atlas built at once ([`super::DecalAtlas::build`]) inside it.

use etagere::{AllocId, AtlasAllocator, size2};

use super::DecalError;
use super::atlas::{
    AtlasEntry, DecalAtlas, DecalAtlasConfig, Slot, blit_with_gutter, downsample, padded_size,
};
use super::image::{Channel, DecalImage, DecalMaterial};

/// The free and taken room of a packed decal atlas.
#[derive(Clone)]
pub(crate) struct AtlasSpace {
    allocator: AtlasAllocator,
    size: u32,
    mip_levels: u32,
    gutter: u32,
}

impl std::fmt::Debug for AtlasSpace {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "AtlasSpace({0}², {1} texels free)",
            self.size,
            self.allocator.free_space()
        )
    }
}

/// A material placed in the atlas: its entry and allocation, and its rectangle's texels.
pub(crate) struct PlacedMaterial {
    pub(crate) entry: AtlasEntry,
    pub(crate) allocation: AllocId,
    /// The rectangle at level 0: corner and size (gutters and rounding included).
    pub(crate) corner: (u32, u32),
    pub(crate) size: (u32, u32),
    /// `levels[channel][level]`: RGBA8 rows of the rectangle at that level
    /// (`size >> level`).
    pub(crate) levels: [Vec<Vec<u8>>; Channel::COUNT],
}

impl AtlasSpace {
    /// Packs `materials` ([`DecalAtlas::build`]) and keeps the atlas's room: the atlas, its
    /// room, and each material's allocation.
    pub(crate) fn build(
        materials: &[DecalMaterial],
        config: DecalAtlasConfig,
    ) -> Result<(DecalAtlas, Self, Vec<AllocId>), DecalError> {
        let (atlas, allocator, allocations) = DecalAtlas::build_with_allocator(materials, config)?;
        let space = Self {
            allocator,
            size: atlas.size,
            mip_levels: atlas.mip_levels,
            gutter: atlas.gutter,
        };
        Ok((atlas, space, allocations))
    }

    /// Allocates `m` in free room and builds its rectangle's levels, or `None` when no free
    /// room is large enough (the atlas must then be packed again).
    pub(crate) fn place(&mut self, m: &DecalMaterial) -> Option<PlacedMaterial> {
        let (width, height) = padded_size(m, self.gutter);
        let allocation = self
            .allocator
            .allocate(size2(width as i32, height as i32))?;
        let corner = (
            allocation.rectangle.min.x as u32,
            allocation.rectangle.min.y as u32,
        );
        let (w, h) = (m.base_color.width, m.base_color.height);
        let levels = Channel::ALL.map(|channel| {
            let neutral = DecalImage::solid(w, h, channel.neutral());
            let image = m.channel(channel).unwrap_or(&neutral);
            let mut base = vec![0u8; (width * height * 4) as usize];
            let slot = Slot {
                corner: (0, 0),
                size: (width, height),
                gutter: self.gutter,
            };
            blit_with_gutter(&mut base, width, image, slot);
            let mut chain = vec![base];
            for level in 1..self.mip_levels {
                let above = &chain[level as usize - 1];
                let side = (width >> (level - 1), height >> (level - 1));
                chain.push(downsample(above, side, channel));
            }
            chain
        });
        Some(PlacedMaterial {
            entry: AtlasEntry::at(corner, m, self.gutter, self.size),
            allocation: allocation.id,
            corner,
            size: (width, height),
            levels,
        })
    }

    /// Gives a removed material's rectangle back.
    pub(crate) fn give_back(&mut self, allocation: AllocId) {
        self.allocator.deallocate(allocation);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A material whose every channel varies texel by texel (so a wrong level or offset shows).
    fn patterned(name: &str, w: u32, h: u32, seed: u32) -> DecalMaterial {
        let image = |k: u32| {
            DecalImage::from_fn(w, h, move |x, y| {
                let v = (x * 37 + y * 101 + seed * 53 + k * 17) % 251;
                [
                    v as u8,
                    (255 - v) as u8,
                    ((v * 7) % 256) as u8,
                    128 + (v % 128) as u8,
                ]
            })
        };
        DecalMaterial {
            name: name.into(),
            base_color: image(0),
            normal: Some(image(1)),
            orm: Some(image(2)),
            emissive: None,
        }
    }

    /// The `(width, height)` rectangle at `corner` of `size`-wide RGBA8 rows.
    fn crop(texels: &[u8], size: u32, corner: (u32, u32), (w, h): (u32, u32)) -> Vec<u8> {
        (0..h)
            .flat_map(|y| {
                let start = (((corner.1 + y) * size + corner.0) * 4) as usize;
                texels[start..start + (w * 4) as usize].to_vec()
            })
            .collect()
    }

    #[test]
    fn a_material_placed_later_has_the_levels_a_whole_atlas_gives_it() {
        let config = DecalAtlasConfig {
            max_size: 256,
            mip_levels: 4,
        };
        let (a, b) = (patterned("a", 70, 40, 1), patterned("b", 30, 38, 2));
        let whole = DecalAtlas::build(&[a.clone(), b.clone()], config).expect("fits");
        let (alone, mut space, _) = AtlasSpace::build(&[a], config).expect("fits");
        let placed = space.place(&b).expect("room left");
        assert_eq!(placed.size, padded_size(&b, whole.gutter));
        let [x, y, ..] = whole.entries[1].texels;
        let corner = (x - whole.gutter, y - whole.gutter);
        assert_eq!(
            whole.size, alone.size,
            "the same atlas side, so the same levels"
        );
        for channel in Channel::ALL {
            for level in 0..config.mip_levels {
                let expected = crop(
                    &whole.levels[channel as usize][level as usize],
                    whole.size >> level,
                    (corner.0 >> level, corner.1 >> level),
                    (placed.size.0 >> level, placed.size.1 >> level),
                );
                assert!(
                    placed.levels[channel as usize][level as usize] == expected,
                    "{channel:?} level {level} differs from the whole atlas's"
                );
            }
        }
    }

    #[test]
    fn room_given_back_is_placed_again_and_a_full_atlas_says_so() {
        let config = DecalAtlasConfig {
            max_size: 64,
            mip_levels: 3,
        };
        let big = patterned("big", 44, 44, 3);
        let (_, mut space, allocations) =
            AtlasSpace::build(std::slice::from_ref(&big), config).expect("fits");
        assert!(space.place(&big).is_none(), "a second one does not fit");
        space.give_back(allocations[0]);
        let again = space.place(&big).expect("the room given back");
        assert_eq!(again.entry.texels[2..], [44, 44]);
    }
}
