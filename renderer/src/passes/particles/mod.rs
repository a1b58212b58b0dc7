//! The particle passes' GPU parts: the fixed-step simulation of a [`ParticleSystem`] in
//! compute (`simulate`) and the bitonic back-to-front sort (`sort`).
//!
//! [`ParticleSystem`]: crate::particles::ParticleSystem

pub mod simulate;
pub mod sort;

pub use simulate::{ParticleSimulation, SimCounters};
pub use sort::GpuSort;
