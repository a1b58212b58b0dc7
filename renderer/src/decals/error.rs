//! What can go wrong with decals, their materials and their files.

use std::path::PathBuf;

/// What can be wrong with decals, their materials or their files.
#[derive(Debug, thiserror::Error)]
pub enum DecalError {
    #[error("decal atlas: {0}")]
    AtlasConfig(String),
    #[error(
        "{materials} decal materials ({texels} texels with gutters) do not fit a {max_size}² \
         atlas: use fewer or smaller decal images, or raise the atlas size"
    )]
    AtlasFull {
        materials: usize,
        texels: u64,
        max_size: u32,
    },
    #[error("decal material {name:?}, {channel} channel: the image {reason}")]
    Material {
        name: String,
        /// The channel's name ([`super::Channel::name`]).
        channel: &'static str,
        reason: String,
    },
    #[error("decal image {path}: {reason}")]
    Image { path: PathBuf, reason: String },
    #[error("decal {index}: {reason}")]
    Decal { index: usize, reason: String },
    #[error(
        "{count} decals do not fit one storage binding of decal records on this device (at \
         most {max}): use fewer decals"
    )]
    TooMany { count: usize, max: usize },
    #[error("decal file {path}: {reason}")]
    Sidecar { path: PathBuf, reason: String },
}
