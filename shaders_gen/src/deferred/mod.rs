//! Deferred shading over the forward module's G-buffer (`forward::fs_gbuffer`): tile-based
//! deferred shading in one compute dispatch (`tbdr`, reference 000), and the expansion of its
//! resolved image into a multisampled target for what is drawn over it (`hdr_expand`).

pub mod expand;
pub mod tiled_shading;

pub use expand::hdr_expand;
pub use tiled_shading::tbdr;
