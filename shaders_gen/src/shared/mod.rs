//! DSL libraries: the GPU code several shader modules share, written once.
//!
//! Each module here is a `#[shader_dsl::library]`: it is compiled and validated on its own, and
//! a `#[shader_dsl::shader(.., uses(crate::shared::name))]` module merges its items in. The
//! using modules re-export the library's host types, so `forward::GpuLight` and
//! `pbr::GpuLight` are one Rust type.

pub mod append;
pub mod brdf;
pub mod camera;
pub mod decal;
pub mod grid;
pub mod material;
pub mod normals;
pub mod shadow;

pub use append::cull_append;
pub use brdf::pbr;
pub use camera::view;
pub use decal::decal_apply;
pub use grid::light_grid;
pub use material::material_uv;
pub use normals::octahedral;
pub use shadow::shadow_atlas;
