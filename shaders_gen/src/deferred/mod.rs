//! Deferred shading over the forward module's G-buffer (`forward::fs_gbuffer`): tile-based
//! deferred shading in one compute dispatch (`tbdr`, reference 000), the overlay of what is
//! drawn over its image with MSAA (`hdr_overlay`) and its erase (`overlay_erase`), and
//! traditional deferred shading's light volumes (`light_volume`). Reading the G-buffer (its
//! bindings, samples, the edge test and shading points) is the `tbdr_gbuffer` library, which
//! uses the shared light-grid, shadow-atlas and octahedral libraries.

pub mod gbuffer_read;
pub mod light_volumes;
pub mod overlay;
pub mod tiled_shading;

pub use light_volumes::light_volume;
pub use overlay::{hdr_overlay, overlay_erase};
pub use tiled_shading::tbdr;
