//! The deferred paths' own passes: the G-buffer (`gbuffer`) and tile-based deferred shading
//! in compute (`tiled_shading`). Blended surfaces and particles are drawn over their image by
//! the forward and particle passes.

pub mod gbuffer;
pub mod tiled_shading;

pub use gbuffer::GBufferPass;
pub use tiled_shading::{TbdrPass, TbdrRecord};
