//! Host side of clustered culling: the fine kernel `shaders_gen::culling::cluster_cull` on top
//! of the shared [`super::hierarchy`]. Froxels are the screen tiles × exponential depth slices.

use glam::{Mat4, UVec2};
use shaders_gen::culling::cluster_cull::{self, MAX_LISTS, Tile, VariantKey};

use super::ClusterGrid;
use super::CullError;
#[cfg(doc)]
use super::hierarchy::DepthInput;
use super::hierarchy::{CullHierarchy, CullItems, CullView, HierarchyShape, MethodParams};
use crate::GpuContext;

/// Settings of the clustered culling pass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClusterCullConfig {
    pub grid: ClusterGrid,
    /// MSAA sample count of the depth buffer (used to find occupied froxels).
    pub msaa: u32,
    /// The depths are the compute rasteriser's buffer of samples, not a depth buffer
    /// ([`crate::frame_data::VisibilityRaster::Compute`]; [`DepthInput::Samples`]).
    pub vis64: bool,
    /// Give froxels without any depth sample empty lists.
    pub skip_empty: bool,
    /// Skip the super-tile level: every tile tests every item (for comparison).
    pub brute_force: bool,
    /// Candidate slots per super-tile (see [`HierarchyShape::coarse_slots`]).
    pub coarse_slots: Option<u32>,
    /// Entries the index list holds at creation (`levels.shape.index_capacity` after
    /// `levels.grow`).
    pub index_capacity: u32,
    pub item_capacity: u32,
}

/// The fine kernel's variant key for a configuration.
pub fn variant_key(config: &ClusterCullConfig) -> Result<VariantKey, CullError> {
    let tile = config.grid.tile;
    Ok(VariantKey {
        tile: Tile::from_value(tile).ok_or(CullError::TileSize(tile))?,
    })
}

/// Clustered light culling for one target size and configuration.
#[derive(Debug)]
pub struct ClusteredCulling {
    pub config: ClusterCullConfig,
    /// The buffers and dispatches (tiles, lists, capacities now in use).
    pub levels: CullHierarchy,
}

impl ClusteredCulling {
    pub fn new(
        gpu: &GpuContext,
        config: ClusterCullConfig,
        width: u32,
        height: u32,
    ) -> Result<Self, CullError> {
        let g = config.grid;
        if g.slices == 0 || g.slices > MAX_LISTS || !(g.near > 0.0 && g.far > g.near) {
            return Err(CullError::Grid(format!("{g:?}")));
        }
        let shape = HierarchyShape {
            tile: g.tile,
            msaa: config.msaa,
            vis64: config.vis64,
            lists_per_tile: g.slices,
            index_capacity: config.index_capacity,
            item_capacity: config.item_capacity,
            brute_force: config.brute_force,
            coarse_slots: config.coarse_slots,
        };
        let fine = cluster_cull::variant(variant_key(&config)?);
        Ok(Self {
            config,
            levels: CullHierarchy::new(gpu, shape, fine, width, height)?,
        })
    }

    /// Uploads the camera and the items' world-space bounding spheres.
    pub fn upload(
        &self,
        gpu: &GpuContext,
        view: Mat4,
        projection: Mat4,
        screen: UVec2,
        items: CullItems<'_>,
    ) -> Result<(), CullError> {
        let g = self.config.grid;
        let camera = CullView {
            view,
            projection,
            screen,
        };
        let method = MethodParams {
            transparent: false,
            all_slices: !self.config.skip_empty,
            slices: g.slices,
            slice_near: g.near,
            slice_far: g.far,
        };
        let params = self.levels.params(&camera, &items, method);
        self.levels.upload(gpu, &params, &items)
    }
}
