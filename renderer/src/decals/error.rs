//! What can go wrong with decals, their materials and their files.

use std::path::PathBuf;

/// What can be wrong with decals, their materials or their files.
#[derive(Debug, thiserror::Error)]
pub enum DecalError {
    /// A [`super::DecalAtlasConfig`] out of range: `mip_levels` not 1 to 8, or `max_size` not a
    /// power of two of at least 64.
    #[error("decal atlas: {0}")]
    AtlasConfig(String),
    /// The materials with their gutters do not fit a `max_size` square atlas.
    #[error(
        "{materials} decal materials ({texels} texels with gutters) do not fit a {max_size}² \
         atlas: use fewer or smaller decal images, or raise the atlas size"
    )]
    AtlasFull {
        /// How many materials were packed.
        materials: usize,
        /// Their texels at level 0, gutters included.
        texels: u64,
        /// The configured largest atlas side.
        max_size: u32,
    },
    /// A channel image of a material is empty, over [`super::MAX_DECAL_IMAGE`] on a side, not
    /// the base colour's size, or has the wrong byte count.
    #[error("decal material {name:?}, {channel} channel: the image {reason}")]
    Material {
        /// The material's name.
        name: String,
        /// The channel's name ([`super::Channel::name`]).
        channel: &'static str,
        /// What is wrong with the image.
        reason: String,
    },
    /// A PNG cannot be read or decoded.
    #[error("decal image {path}: {reason}")]
    Image {
        /// The image file.
        path: PathBuf,
        /// The `image` crate's error.
        reason: String,
    },
    /// A decal fails [`super::DecalSet::validate`]: unknown material, degenerate or sheared
    /// box, blend outside 0..=1, or a fade that does not run from start to end.
    #[error("decal {index}: {reason}")]
    Decal {
        /// The decal's index in [`super::DecalSet::decals`].
        index: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// More decals than one storage binding holds on the device.
    #[error(
        "{count} decals do not fit one storage binding of decal records on this device (at \
         most {max}): use fewer decals"
    )]
    TooMany {
        /// Decals in the set.
        count: usize,
        /// The most the device takes.
        max: usize,
    },
    /// A JSON sidecar cannot be read or parsed, defines a material twice, names an unknown
    /// one, or one of its images or decals is invalid.
    #[error("decal file {path}: {reason}")]
    Sidecar {
        /// The sidecar file.
        path: PathBuf,
        /// What is wrong, naming the decal or material.
        reason: String,
    },
}
