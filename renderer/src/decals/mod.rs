//! Decals: textures projected through oriented boxes onto whatever surfaces lie inside them
//! (DOOM 2016's clustered decals, reference 004). GPU-free: the decal items ([`Decal`], their
//! boxes and the separating-axis tests the culling reference needs), the decal atlas
//! (`DecalAtlas`: every material's channels packed with `etagere`, mip levels and gutters, and
//! materials added and removed in place), the
//! built-in procedural materials, PNG loading, the JSON sidecar and seeded placement on a
//! scene's surfaces.
//!
//! On the GPU, `crate::frame_data::GpuDecals` holds the records and culling boxes in layer order
//! and the atlas textures; `crate::culling` lists the boxes in the cell lists beside the lights
//! and forward shading applies them before lighting (`shaders_gen::shared::decal_apply`).

mod atlas;
mod atlas_space;
mod decal;
mod error;
mod image;
pub mod obb;

pub mod procedural;
#[cfg(feature = "json")]
pub mod sidecar;

pub use atlas::DecalAtlasConfig;
internal_use!(atlas::AtlasEntry);
#[cfg(feature = "internals")]
#[doc(hidden)]
pub use atlas::DecalAtlas;
pub(crate) use atlas_space::{AtlasSpace, PlacedMaterial};
pub use decal::{Decal, DecalSet, box_on_surface};
pub use error::DecalError;
pub use image::{Channel, DecalImage, DecalMaterial, MAX_DECAL_IMAGE};
pub use obb::OrientedBox;
