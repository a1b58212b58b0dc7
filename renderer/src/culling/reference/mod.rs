//! Independent CPU reference for light culling, written from the literature (Harada's Forward+,
//! the tiled/2.5D tutorial in reference 000, Olsson's clustered shading), not from the kernels.
//!
//! Conventions shared with the GPU kernels:
//! - right-handed view space, camera looking down −Z; "view depth" is `-z`;
//! - wgpu depth: 0 at the near plane, 1 at the far plane; a sample with depth 1 is sky and
//!   belongs to no surface;
//! - pixel `(x, y)` has NDC `x = 2 (x / w) − 1`, `y = 1 − 2 (y / h)`; tile `(i, j)` of size `t`
//!   spans pixels `[i t, (i + 1) t)` without clamping to the screen edge;
//! - every light is a sphere in view space (spot lights use their cone's bounding sphere); every
//!   decal an oriented box in view space.
//!
//! [`cull`] gives each tile or cluster its sorted list of lights that pass the method's test,
//! plus the lights whose test was too close to call in `f32` (see [`Borderline`]).
//! [`exact`] gives, per sample, the lights whose sphere really contains the sample's surface
//! point, and [`exact::cull_efficiency`] compares the two. [`cull_boxes`] does the same for
//! decal boxes; a box that contains a sample's point must be in the sample's cell.
//! [`cone`] finds a spot light's bounding sphere its own way, from the sector the light
//! reaches, to check the renderer's closed form ([`LightSphere::spot`]).

mod cell_bounds;
mod cells;
pub mod cone;
pub mod exact;
mod frustum;
mod methods;
#[cfg(test)]
mod ortho_tests;

pub use super::depth::{DepthBuffer, standard_sample_offset};
pub use super::vocabulary::{
    ClusterGrid, CullCamera, DEPTH_MASK_CELLS, LightSphere, Method, Plane, SUPER_TILE_PIXELS,
};
pub use cells::{Borderline, CellLists};
pub use frustum::tile_side_planes;
pub use methods::{cull, cull_boxes, cull_brute_force};
