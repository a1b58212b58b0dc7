//! The shadow-atlas pass's own shaders: drawing casters into atlas regions, and composing a
//! region from the static cache.

pub mod casters;

pub use casters::{shadow_caster, shadow_compose};
