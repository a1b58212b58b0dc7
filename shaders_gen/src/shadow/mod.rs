//! The shadow-atlas pass's own shaders: culling casters per region, drawing them into atlas
//! regions, composing a region from the static cache, and the atlas debug view.

pub mod atlas_view;
pub mod casters;
pub mod cull;

pub use atlas_view::shadow_atlas_view;
pub use casters::{shadow_caster, shadow_compose};
pub use cull::shadow_cull;
