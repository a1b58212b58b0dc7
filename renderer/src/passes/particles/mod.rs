//! The particle passes' GPU parts: the fixed-step simulation of a [`ParticleSystem`] in
//! compute (`simulate`), the lighting atlas's layout (`atlas`: region sizes from projected
//! size, allocated on the GPU, shrunk and reported when full) and the bitonic back-to-front
//! sort (`sort`).
//!
//! [`ParticleSystem`]: crate::particles::ParticleSystem

pub mod atlas;
mod bind;
pub mod simulate;
pub mod sort;

pub use atlas::{AtlasReport, ParticleAtlas};
pub use simulate::{ParticleSimulation, SimCounters};
pub use sort::GpuSort;
