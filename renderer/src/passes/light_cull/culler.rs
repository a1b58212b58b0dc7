//! The light culler of the configured path: which culling hierarchy a frame's light culling
//! runs, and what it reads and writes.

use std::sync::Arc;

use crate::culling::Method;
use crate::culling::clustered::ClusteredCulling;
use crate::culling::hierarchy::CullHierarchy;
use crate::culling::lists::LightLists;
use crate::culling::tiled::TiledCulling;

/// The light culler of the configured path.
#[derive(Debug, Clone)]
pub enum Culler {
    /// No culling: every light shades every pixel.
    Naive,
    /// Screen tiles (tiled and 2.5D).
    Tiled(Arc<TiledCulling>),
    /// View-space clusters.
    Clustered(Arc<ClusteredCulling>),
}

impl Culler {
    /// The culling hierarchy of this culler (none on the naive paths).
    pub fn levels(&self) -> Option<&CullHierarchy> {
        match self {
            Self::Tiled(c) => Some(&c.levels),
            Self::Clustered(c) => Some(&c.levels),
            Self::Naive => None,
        }
    }

    /// Whether it reads the compute rasteriser's samples rather than a depth buffer.
    pub(super) fn reads_samples(&self) -> bool {
        self.levels().is_some_and(|l| l.shape.vis64)
    }

    /// The light lists this culler writes (none on the naive paths).
    pub fn lists(&self) -> Option<&LightLists> {
        self.levels().map(|l| &l.lists)
    }

    /// Whether the culling pass reads the depth buffer (every culled path does: tile depth
    /// bounds bound the super-tiles and tiles, and mark the occupied froxels).
    pub fn reads_depth(&self) -> bool {
        !matches!(self, Self::Naive)
    }

    /// Bytes the culling reads a sample of the frame: a 32-bit depth, or the compute
    /// rasteriser's 64-bit sample; none on the naive paths.
    pub fn depth_bytes_per_sample(&self) -> u32 {
        match (self.reads_depth(), self.reads_samples()) {
            (false, _) => 0,
            (true, false) => 4,
            (true, true) => 8,
        }
    }

    /// The culling method, as the CPU reference names it.
    pub fn method(&self) -> Option<Method> {
        match self {
            Self::Tiled(t) if t.config.depth_mask => Some(Method::Depth25 {
                tile: t.config.tile,
                transparent: t.config.transparent_lists,
            }),
            Self::Tiled(t) => Some(Method::Tiled {
                tile: t.config.tile,
                transparent: t.config.transparent_lists,
            }),
            Self::Clustered(k) => Some(Method::Clustered {
                grid: k.config.grid,
                skip_empty: k.config.skip_empty,
            }),
            Self::Naive => None,
        }
    }
}
