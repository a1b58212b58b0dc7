//! The deferred paths' own passes: the G-buffer (`gbuffer`), tile-based deferred shading in
//! compute (`tiled_shading`, which is also traditional deferred shading's base pass) and
//! traditional deferred shading's light volumes (`light_volumes`). Blended surfaces and
//! particles are drawn over their image by the forward and particle passes.

pub mod gbuffer;
pub mod light_volumes;
pub mod tiled_shading;

pub use gbuffer::GBufferPass;
pub use light_volumes::LightVolumePass;
pub use tiled_shading::TbdrPass;
#[cfg(any(test, feature = "internals"))]
pub use tiled_shading::TbdrRecord;
