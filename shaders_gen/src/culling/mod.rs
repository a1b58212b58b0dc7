//! Culling kernels: which items (lights and decals, in their own ranges of the item list) can
//! touch each screen tile or froxel, (`instance_cull`, `occlusion_cull` with its depth
//! pyramid) which of the scene's draws a view sees, (`draw_compact`) its drawn slots packed per
//! batch in slot order, and (`blended_order`) in which order its blended draws are drawn.
//!
//! Culling is hierarchical, in three dispatches: `cull_prepare::tile_depth` (per tile: depth
//! bounds, 2.5D mask, occupied slices), `cull_prepare::coarse_cull` (per 128×128-pixel
//! super-tile: every item against the super-tile's frustum), then the fine level, `tile_cull`
//! or `cluster_cull`, which tests only its super-tile's candidates. Lists are counted before
//! they are written, so none is ever cut short.
//!
//! The conventions are those of the CPU reference in `renderer::culling::reference`:
//! right-handed view space looking down −Z, wgpu depth (1.0 = far/sky), tile planes from the
//! projection rows (Gribb/Hartmann), tile depth bounds over every MSAA sample with sky excluded.
//!
//! Items are ordered by type in the item buffer (lights first; decals and probes will follow in
//! their own ranges), so a later item type extends the same lists without a redesign.

pub mod blended;
pub mod clustered;
pub mod compact;
pub mod instances;
pub mod occlusion;
pub mod prepare;
pub mod tiled;

pub use blended::blended_order;
pub use clustered::cluster_cull;
pub use compact::draw_compact;
pub use instances::instance_cull;
pub use occlusion::{depth_pyramid_reduce, depth_pyramid_seed, occlusion_cull};
pub use prepare::cull_prepare;
pub use tiled::tile_cull;
