//! Forward shading: the depth pre-pass, the material frame and glTF's metallic-roughness
//! material in it (forward shading over the naive, tiled or clustered light lists, and the
//! G-buffer), the light-count heatmap debug view, and tonemapping to sRGB (a full-screen pass
//! or a compute kernel).
//!
//! Light-list conventions are those of [`crate::culling`]: `GRID` holds `(offset, count)` per
//! tile or froxel and `INDICES` the light indices, exactly as `tile_cull` and `cluster_cull`
//! write them; light `i` of the list is entry `i` of the culling pass's item buffer and of
//! `forward`'s `LIGHTS`.

pub mod depth_prepass;
pub mod frame;
pub mod light_heatmap;
pub mod shading;
pub mod tonemapping;

pub use depth_prepass::prez;
pub use frame::{material_frame, material_surface};
pub use light_heatmap::heatmap;
pub use shading::{forward, gltf_material};
pub use tonemapping::{tone_curves, tonemap, tonemap_compute};
