//! Host side of tiled and 2.5D culling: the fine kernel `shaders_gen::culling::tile_cull` on top
//! of the shared [`super::hierarchy`], with an opaque list per tile and, when blended surfaces
//! are shaded, a transparent list.

use glam::{Mat4, UVec2};
use shaders_gen::culling::tile_cull::{self, Tile, VariantKey};

use super::CullError;
use super::hierarchy::{CullHierarchy, CullItems, CullView, HierarchyShape, MethodParams};
use crate::GpuContext;

/// Settings of the tiled culling pass.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TileCullConfig {
    /// Tile edge in pixels: 8, 16 or 32.
    pub tile: u32,
    /// MSAA sample count of the depth buffer: 1, 2, 4 or 8.
    pub msaa: u32,
    /// 2.5D culling: test items against the tile's 32-cell geometry depth mask too.
    pub depth_mask: bool,
    /// Blended surfaces, which the pre-Z depth does not hold, are shaded: write a second list
    /// per tile, from the near plane to the tile's farthest opaque sample (grid entries
    /// `tile_count..2·tile_count`). The opaque lists stay as tight as without.
    pub transparent_lists: bool,
    /// Skip the super-tile level: every tile tests every item (for comparison).
    pub brute_force: bool,
    /// Candidate slots per super-tile (see [`HierarchyShape::coarse_slots`]).
    pub coarse_slots: Option<u32>,
    /// Entries the index list holds.
    /// Entries the index list holds at creation (`levels.shape.index_capacity` after
    /// `levels.grow`).
    pub index_capacity: u32,
    /// Items the item buffer holds.
    pub item_capacity: u32,
}

/// The fine kernel's variant key for a configuration.
pub fn variant_key(config: &TileCullConfig) -> Result<VariantKey, CullError> {
    Ok(VariantKey {
        tile: Tile::from_value(config.tile).ok_or(CullError::TileSize(config.tile))?,
        depth_mask: config.depth_mask,
    })
}

/// Tiled (or 2.5D) light culling for one target size and configuration.
#[derive(Debug)]
pub struct TiledCulling {
    pub config: TileCullConfig,
    /// The buffers and dispatches (tiles, lists, capacities now in use).
    pub levels: CullHierarchy,
}

impl TiledCulling {
    pub fn new(
        gpu: &GpuContext,
        config: TileCullConfig,
        width: u32,
        height: u32,
    ) -> Result<Self, CullError> {
        let shape = HierarchyShape {
            tile: config.tile,
            msaa: config.msaa,
            // Tiled lists are not on the visibility path.
            vis64: false,
            lists_per_tile: 1 + u32::from(config.transparent_lists),
            index_capacity: config.index_capacity,
            item_capacity: config.item_capacity,
            brute_force: config.brute_force,
            coarse_slots: config.coarse_slots,
        };
        let fine = tile_cull::variant(variant_key(&config)?);
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
        let camera = CullView {
            view,
            projection,
            screen,
        };
        let method = MethodParams {
            transparent: self.config.transparent_lists,
            ..MethodParams::default()
        };
        let params = self.levels.params(&camera, &items, method);
        self.levels.upload(gpu, &params, &items)
    }
}
