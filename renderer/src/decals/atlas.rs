//! The decal atlas: every decal material's channels packed once with `etagere`, at the same
//! place in one texture per channel (base colour, normal, occlusion-roughness-metalness,
//! emissive), with mip levels and gutters wide enough that no level ever filters one decal into
//! another.
//!
//! Gutters: with `L` mip levels every allocation is aligned to, and padded by, `P = 2^(L−1)`
//! texels (etagere's size alignment keeps positions on that grid). Level `k` halves everything,
//! so each material keeps a gutter of `P / 2^k ≥ 1` texel of its own edge texels at every level,
//! and a 2×2 box filter never mixes two allocations. Gutters repeat the nearest edge texel, so a
//! bilinear tap just outside a decal's rectangle reads the decal itself.

use etagere::{AllocId, AllocatorOptions, AtlasAllocator, size2};
use glam::Vec4;

use super::DecalError;
use super::image::{Channel, DecalImage, DecalMaterial};

/// How an atlas is built.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DecalAtlasConfig {
    /// Largest side of the atlas textures (texels, a power of two).
    pub max_size: u32,
    /// Mip levels, 1 to 8 (the gutter is `2^(levels − 1)` texels).
    pub mip_levels: u32,
}

impl Default for DecalAtlasConfig {
    fn default() -> Self {
        Self {
            max_size: 4096,
            mip_levels: 5,
        }
    }
}

/// Where one material lives in the atlas.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AtlasEntry {
    /// The material's texels at level 0: left, top, width, height (gutter excluded).
    pub texels: [u32; 4],
    /// The same in UV: corner and size.
    pub uv: Vec4,
    /// Bit `c` set when the material has channel `c` ([`Channel`]); absent channels hold neutral
    /// texels and shading skips them.
    pub channels: u32,
}

/// The packed atlas: per channel, per mip level, RGBA8 texels (`size >> level` square).
#[derive(Debug, Clone, PartialEq)]
pub struct DecalAtlas {
    /// Side of every channel's level 0, in texels (a power of two, 64 to `max_size`).
    pub size: u32,
    /// Mip levels per channel, as configured.
    pub mip_levels: u32,
    /// Gutter around each material at level 0, in texels.
    pub gutter: u32,
    /// `levels[channel][level]`: RGBA8 rows, `size >> level` texels square.
    pub levels: [Vec<Vec<u8>>; Channel::COUNT],
    /// One entry per material, in the order given.
    pub entries: Vec<AtlasEntry>,
}

impl DecalAtlas {
    /// Packs `materials` into the smallest square power-of-two atlas (at least 64, at most
    /// `config.max_size`) that holds them all with their gutters.
    #[cfg(any(test, feature = "internals"))]
    pub fn build(
        materials: &[DecalMaterial],
        config: DecalAtlasConfig,
    ) -> Result<Self, DecalError> {
        Ok(Self::build_with_allocator(materials, config)?.0)
    }

    /// [`DecalAtlas::build`], with the allocator of its room and each material's allocation in
    /// it (`AtlasSpace::build` keeps them to add and remove materials in place later).
    pub(super) fn build_with_allocator(
        materials: &[DecalMaterial],
        config: DecalAtlasConfig,
    ) -> Result<(Self, AtlasAllocator, Vec<AllocId>), DecalError> {
        if !(1..=8).contains(&config.mip_levels) {
            return Err(DecalError::AtlasConfig(format!(
                "mip_levels {}: use 1 to 8",
                config.mip_levels
            )));
        }
        if !config.max_size.is_power_of_two() || config.max_size < 64 {
            return Err(DecalError::AtlasConfig(format!(
                "max_size {}: use a power of two of at least 64",
                config.max_size
            )));
        }
        for m in materials {
            m.check()?;
        }
        let gutter = 1u32 << (config.mip_levels - 1);
        let (size, allocator, placed) = pack(materials, gutter, config.max_size)?;
        let padded = |m: &DecalMaterial| padded_size(m, gutter);
        let mut base: [Vec<u8>; Channel::COUNT] =
            std::array::from_fn(|_| vec![0u8; (size * size * 4) as usize]);
        let mut entries = Vec::with_capacity(materials.len());
        for (m, &((x, y), _)) in materials.iter().zip(&placed) {
            let (w, h) = (m.base_color.width, m.base_color.height);
            for channel in Channel::ALL {
                let neutral = DecalImage::solid(w, h, channel.neutral());
                let image = m.channel(channel).unwrap_or(&neutral);
                let slot = Slot {
                    corner: (x, y),
                    size: padded(m),
                    gutter,
                };
                blit_with_gutter(&mut base[channel as usize], size, image, slot);
            }
            entries.push(AtlasEntry::at((x, y), m, gutter, size));
        }
        let levels = std::array::from_fn(|c| {
            let channel = Channel::ALL[c];
            let mut chain = vec![std::mem::take(&mut base[c])];
            for level in 1..config.mip_levels {
                let above = &chain[level as usize - 1];
                let side = size >> (level - 1);
                chain.push(downsample(above, (side, side), channel));
            }
            chain
        });
        let atlas = Self {
            size,
            mip_levels: config.mip_levels,
            gutter,
            levels,
            entries,
        };
        Ok((
            atlas,
            allocator,
            placed.into_iter().map(|(_, id)| id).collect(),
        ))
    }
}

impl AtlasEntry {
    /// The entry of material `m` allocated at `corner` of a `size`² atlas with `gutter`.
    pub(super) fn at(corner: (u32, u32), m: &DecalMaterial, gutter: u32, size: u32) -> Self {
        let ((x, y), (w, h)) = (corner, (m.base_color.width, m.base_color.height));
        let s = size as f32;
        Self {
            texels: [x + gutter, y + gutter, w, h],
            uv: Vec4::new(
                (x + gutter) as f32 / s,
                (y + gutter) as f32 / s,
                w as f32 / s,
                h as f32 / s,
            ),
            channels: m.channel_mask(),
        }
    }
}

/// A material's allocation: its corner and its id.
type Allocation = ((u32, u32), AllocId);

/// The smallest atlas that holds every material: its side, its allocator, and each material's
/// allocation.
fn pack(
    materials: &[DecalMaterial],
    gutter: u32,
    max_size: u32,
) -> Result<(u32, AtlasAllocator, Vec<Allocation>), DecalError> {
    let padded = |m: &DecalMaterial| padded_size(m, gutter);
    let area: u64 = materials
        .iter()
        .map(|m| {
            let (w, h) = padded(m);
            u64::from(w) * u64::from(h)
        })
        .sum();
    let mut size = 64u32;
    while u64::from(size) * u64::from(size) < area && size < max_size {
        size *= 2;
    }
    loop {
        let options = AllocatorOptions {
            alignment: size2(gutter as i32, gutter as i32),
            ..Default::default()
        };
        let mut allocator = AtlasAllocator::with_options(size2(size as i32, size as i32), &options);
        let placed: Option<Vec<Allocation>> = materials
            .iter()
            .map(|m| {
                let (w, h) = padded(m);
                let a = allocator.allocate(size2(w as i32, h as i32))?;
                Some(((a.rectangle.min.x as u32, a.rectangle.min.y as u32), a.id))
            })
            .collect();
        match placed {
            Some(p) => return Ok((size, allocator, p)),
            None if size < max_size => size *= 2,
            None => {
                return Err(DecalError::AtlasFull {
                    materials: materials.len(),
                    texels: area,
                    max_size,
                });
            }
        }
    }
}

/// A material's allocation: its image plus a gutter on every side, rounded up to the gutter
/// grid (the allocator's alignment).
pub(super) fn padded_size(m: &DecalMaterial, gutter: u32) -> (u32, u32) {
    let round = |v: u32| (v + 2 * gutter).div_ceil(gutter) * gutter;
    (round(m.base_color.width), round(m.base_color.height))
}

/// Where a material's allocation is: corner, padded size, gutter.
#[derive(Debug, Clone, Copy)]
pub(super) struct Slot {
    pub(super) corner: (u32, u32),
    pub(super) size: (u32, u32),
    pub(super) gutter: u32,
}

/// Copies `image` to `slot`'s corner plus its gutter in RGBA8 rows of `size` texels and fills
/// the rest of the slot (the gutter ring and the rounding beyond it) with the nearest edge
/// texels.
pub(super) fn blit_with_gutter(atlas: &mut [u8], size: u32, image: &DecalImage, slot: Slot) {
    let (w, h) = (image.width, image.height);
    let ((x, y), (sw, sh), gutter) = (slot.corner, slot.size, slot.gutter);
    for ay in 0..sh {
        let sy = ay.saturating_sub(gutter).min(h - 1);
        for ax in 0..sw {
            let sx = ax.saturating_sub(gutter).min(w - 1);
            let from = ((sy * w + sx) * 4) as usize;
            let to = (((y + ay) * size + x + ax) * 4) as usize;
            atlas[to..to + 4].copy_from_slice(&image.rgba[from..from + 4]);
        }
    }
}

/// One mip level down of a `(width, height)` level (2×2 box filter): sRGB channels averaged in
/// linear light, normals renormalised, the rest averaged as stored.
pub(super) fn downsample(above: &[u8], (width, height): (u32, u32), channel: Channel) -> Vec<u8> {
    let (out_width, out_height) = ((width / 2).max(1), (height / 2).max(1));
    let mut out = vec![0u8; (out_width * out_height * 4) as usize];
    for y in 0..out_height {
        for x in 0..out_width {
            let mut sum = [0f32; 4];
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let (sx, sy) = ((2 * x + dx).min(width - 1), (2 * y + dy).min(height - 1));
                let i = ((sy * width + sx) * 4) as usize;
                for c in 0..4 {
                    sum[c] += channel.decode(c, above[i + c]);
                }
            }
            let mut avg = sum.map(|v| v / 4.0);
            if channel == Channel::Normal {
                let n = glam::Vec3::new(avg[0], avg[1], avg[2]).normalize_or(glam::Vec3::Z);
                avg[..3].copy_from_slice(&n.to_array());
            }
            let i = ((y * out_width + x) * 4) as usize;
            for c in 0..4 {
                out[i + c] = channel.encode(c, avg[c]);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn material(name: &str, w: u32, h: u32, rgba: [u8; 4]) -> DecalMaterial {
        DecalMaterial {
            name: name.into(),
            base_color: DecalImage::solid(w, h, rgba),
            normal: None,
            orm: None,
            emissive: None,
        }
    }

    fn texel(atlas: &DecalAtlas, channel: Channel, level: u32, x: u32, y: u32) -> [u8; 4] {
        let size = atlas.size >> level;
        let i = ((y * size + x) * 4) as usize;
        atlas.levels[channel as usize][level as usize][i..i + 4]
            .try_into()
            .unwrap()
    }

    #[test]
    fn entries_are_disjoint_aligned_and_inside_with_their_gutters() {
        let sizes = [(100, 60), (33, 200), (64, 64), (1, 1), (250, 17), (90, 90)];
        let materials: Vec<DecalMaterial> = sizes
            .iter()
            .enumerate()
            .map(|(i, &(w, h))| material(&format!("m{i}"), w, h, [i as u8 * 40, 0, 0, 255]))
            .collect();
        let atlas = DecalAtlas::build(&materials, DecalAtlasConfig::default()).unwrap();
        let g = atlas.gutter;
        assert_eq!(g, 16);
        let padded: Vec<[u32; 4]> = atlas
            .entries
            .iter()
            .map(|e| {
                let [x, y, w, h] = e.texels;
                [x - g, y - g, w + 2 * g, h + 2 * g]
            })
            .collect();
        for (i, a) in padded.iter().enumerate() {
            assert_eq!(
                (a[0] % g, a[1] % g),
                (0, 0),
                "entry {i} is on the gutter grid"
            );
            assert!(
                a[0] + a[2] <= atlas.size && a[1] + a[3] <= atlas.size,
                "entry {i} inside"
            );
            for b in &padded[i + 1..] {
                let apart = a[0] + a[2] <= b[0]
                    || b[0] + b[2] <= a[0]
                    || a[1] + a[3] <= b[1]
                    || b[1] + b[3] <= a[1];
                assert!(apart, "{a:?} overlaps {b:?}");
            }
        }
        assert_eq!(atlas.entries[0].texels[2..], [100, 60]);
        assert!(
            atlas.size <= 1024,
            "smallest atlas that fits: {}",
            atlas.size
        );
    }

    /// Every material a different solid colour: at every level, the texels of each material's
    /// rectangle and of a one-texel ring around it are that colour, so bilinear filtering at the
    /// rectangle's edge, at any level, reads nothing of its neighbours.
    #[test]
    fn no_level_bleeds_between_materials() {
        let colours: Vec<[u8; 4]> = (0..12u8)
            .map(|i| {
                [
                    20 + i * 19,
                    250 - i * 17,
                    ((u32::from(i) * 53) % 255) as u8,
                    255 - i,
                ]
            })
            .collect();
        let materials: Vec<DecalMaterial> = colours
            .iter()
            .enumerate()
            .map(|(i, &c)| material(&format!("m{i}"), 24 + 7 * i as u32, 40 - 2 * i as u32, c))
            .collect();
        let atlas = DecalAtlas::build(&materials, DecalAtlasConfig::default()).unwrap();
        for level in 0..atlas.mip_levels {
            for (e, colour) in atlas.entries.iter().zip(&colours) {
                let [x, y, w, h] = e.texels;
                let lo = |v: u32| (v >> level).saturating_sub(1);
                let hi = |v: u32| (v.div_ceil(1 << level) + 1).min(atlas.size >> level);
                for ty in lo(y)..hi(y + h) {
                    for tx in lo(x)..hi(x + w) {
                        let got = texel(&atlas, Channel::BaseColor, level, tx, ty);
                        let close = got.iter().zip(colour).all(|(a, b)| a.abs_diff(*b) <= 1);
                        assert!(
                            close,
                            "level {level} texel ({tx}, {ty}): {got:?}, want {colour:?}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn gutters_repeat_the_edge_and_absent_channels_are_neutral() {
        let mut m = material("ramp", 4, 2, [0; 4]);
        for (i, t) in m.base_color.rgba.chunks_mut(4).enumerate() {
            t.copy_from_slice(&[i as u8 * 10, 0, 0, 255]);
        }
        let config = DecalAtlasConfig {
            max_size: 64,
            mip_levels: 2,
        };
        let atlas = DecalAtlas::build(&[m], config).unwrap();
        let [x, y, ..] = atlas.entries[0].texels;
        // Left of texel (0, 0) and above it: texel (0, 0); right of (3, 1): (3, 1).
        assert_eq!(texel(&atlas, Channel::BaseColor, 0, x - 2, y - 2)[0], 0);
        assert_eq!(texel(&atlas, Channel::BaseColor, 0, x + 5, y + 3)[0], 70);
        assert_eq!(texel(&atlas, Channel::BaseColor, 0, x + 1, y)[0], 10);
        assert_eq!(
            texel(&atlas, Channel::Normal, 0, x, y),
            Channel::Normal.neutral()
        );
        assert_eq!(atlas.entries[0].channels, 1 << Channel::BaseColor as u32);
    }

    #[test]
    fn linear_mips_keep_srgb_brightness() {
        // Half black, half white (sRGB): the mean in linear light is 0.5, sRGB ≈ 188.
        let mut m = material("checker", 2, 2, [0, 0, 0, 255]);
        m.base_color.rgba[0..4].copy_from_slice(&[255, 255, 255, 255]);
        m.base_color.rgba[12..16].copy_from_slice(&[255, 255, 255, 255]);
        let config = DecalAtlasConfig {
            max_size: 64,
            mip_levels: 2,
        };
        let atlas = DecalAtlas::build(&[m], config).unwrap();
        let [x, y, ..] = atlas.entries[0].texels;
        let got = texel(&atlas, Channel::BaseColor, 1, x / 2, y / 2);
        assert!((186..=190).contains(&got[0]), "{got:?}");
    }

    #[test]
    fn too_much_for_the_largest_atlas_is_a_clear_error() {
        let big: Vec<DecalMaterial> = (0..5)
            .map(|i| material(&format!("m{i}"), 60, 60, [0; 4]))
            .collect();
        let config = DecalAtlasConfig {
            max_size: 128,
            mip_levels: 3,
        };
        let err = DecalAtlas::build(&big, config).unwrap_err().to_string();
        assert!(
            err.contains("5 decal materials") && err.contains("128"),
            "{err}"
        );
        let bad = DecalAtlasConfig {
            max_size: 100,
            mip_levels: 3,
        };
        assert!(DecalAtlas::build(&big, bad).is_err());
    }
}
