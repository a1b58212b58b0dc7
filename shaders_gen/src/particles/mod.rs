//! GPU particles: the fixed-step simulation (`particle_sim`: update, spawn from the dead list,
//! compact), sizing and placing particles in the lighting atlas (`particle_atlas`) and the
//! back-to-front sort of blended particles (`particle_sort`, bitonic), with
//! the records and seeded hash they share (`common::particle_common`).

pub mod atlas;
pub mod common;
pub mod simulate;
pub mod sort;

pub use atlas::particle_atlas;
pub use common::particle_common;
pub use simulate::particle_sim;
pub use sort::particle_sort;
