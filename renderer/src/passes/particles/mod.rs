//! The particle passes and their GPU parts. Passes, in frame order:
//! * [`ParticleSimPass`] (`simulate_pass`): one fixed step of the simulation (`simulate`), then
//!   the lighting atlas's layout (`atlas`: region sizes from projected size, allocated on the
//!   GPU, shrunk and reported when full) and the bitonic back-to-front sort
//!   (`passes::gpu_sort`);
//! * [`ParticleLightPass`] (`light_pass`): every atlas texel lit with the clustered lists,
//!   shadows and ambient (atlas lighting only);
//! * [`ParticleDrawPass`] (`draw_pass`): the blended billboards, lit from the atlas or per
//!   pixel.
//!
//! What they share for one [`ParticleSystem`] is `system::ParticleGpu`.
//!
//! [`ParticleSystem`]: crate::particles::ParticleSystem

pub mod atlas;
pub mod draw_pass;
pub mod light_pass;
pub mod simulate;
pub mod simulate_pass;
pub mod system;

pub use super::gpu_sort::GpuSort;
pub use atlas::{AtlasReport, ParticleAtlas};
pub use draw_pass::ParticleDrawPass;
pub use light_pass::ParticleLightPass;
pub use simulate::ParticleSimulation;
#[cfg(any(test, feature = "internals"))]
pub use simulate::SimCounters;
pub use simulate_pass::ParticleSimPass;
