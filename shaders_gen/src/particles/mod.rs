//! GPU particles: the fixed-step simulation (`particle_sim`: update, spawn from the dead list,
//! compact), sizing and placing particles in the lighting atlas (`particle_atlas`) and the
//! back-to-front sort of blended particles (`particle_sort`, bitonic), lighting the atlas
//! (`particle_light`, a thread per texel) and drawing the billboards (`particle_draw`, lit from
//! the atlas or per pixel), with the records and functions they share
//! (`common::particle_common`) and the light response both lighting paths call
//! (`lighting::particle_lighting`).

pub mod atlas;
pub mod common;
pub mod draw;
pub mod light;
pub mod lighting;
pub mod simulate;
pub mod sort;

pub use atlas::particle_atlas;
pub use common::particle_common;
pub use draw::particle_draw;
pub use light::particle_light;
pub use lighting::particle_lighting;
pub use simulate::particle_sim;
pub use sort::particle_sort;
