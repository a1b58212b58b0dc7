//! Helpers for demos, tools and tests, behind the `demo` feature: seeded procedural lights and
//! decals, the courtyard's look, the lights that cast shadows and the instance that moves in the
//! demo, and the full-screen test pattern. None of it is needed to embed the renderer.

mod decal_scatter;
mod setup;
pub mod test_pattern;

pub use decal_scatter::scatter as scatter_decals;
pub use setup::{
    Rng, courtyard_look, light_space, moving_instance, pick_shadowed, procedural_lights,
};
