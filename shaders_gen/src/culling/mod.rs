//! Light-culling kernels: which items (lights today; decals and probes later, in their own
//! ranges of the item list) can touch each screen tile.
//!
//! The conventions are those of the CPU reference in `renderer::culling::reference`:
//! right-handed view space looking down −Z, wgpu depth (1.0 = far/sky), tile planes from the
//! projection rows (Gribb/Hartmann), tile depth bounds over every MSAA sample with sky excluded.
//!
//! Items are ordered by type in the item buffer (lights first; decals and probes will follow in
//! their own ranges), so a later item type extends the same lists without a redesign.

pub mod clustered;
pub mod tiled;

pub use clustered::cluster_cull;
pub use tiled::tile_cull;
