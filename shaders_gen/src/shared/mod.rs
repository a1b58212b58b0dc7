//! DSL libraries: the GPU code several shader modules share, written once.
//!
//! Each module here is a `#[shader_dsl::library]`: it is compiled and validated on its own, and
//! a `#[shader_dsl::shader(.., uses(crate::shared::name))]` module merges its items in. The
//! using modules re-export the library's host types, so `forward::GpuLight` and
//! `pbr::GpuLight` are one Rust type.
//!
//! They are also the renderer's shader library for other crates: an engine's crate that depends
//! on `shaders_gen` (and `shader-dsl`, `codegen`) writes `uses(shaders_gen::shared::pbr)`, and
//! likewise `view`, `light_set`, `light_lists`, `light_spheres`, `surface_light`, `light_grid`,
//! `shadow_atlas`, `decal_apply`, `octahedral`, `material_uv`, `cull_append`, `box_frustum` and
//! `sample_pattern`; `deferred::gbuffer_read::tbdr_gbuffer` reads the deferred G-buffer. The light libraries
//! (`lights.rs`) are the binding contract of every lit pass's group 0: an engine's pass that
//! uses `light_lists` binds the renderer's light buffers and lists by name through
//! `light_set::Group0` and `light_lists::Group0`.
//!
//! This example is such a crate (a doc test is one): its module uses the PBR library and the
//! G-buffer library (which uses the light-grid, shadow-atlas and octahedral libraries itself, so
//! light-grid is reached twice, named here and through it, and merged once), and its own library
//! uses the octahedral library. Every variant is validated when it builds.
//!
//! ```
//! #[shader_dsl::library(uses(shaders_gen::shared::octahedral))]
//! pub mod normals_again {
//!     pub fn round_trip(n: Vec3) -> Vec3 {
//!         octahedral_decode(octahedral_encode(n))
//!     }
//! }
//!
//! #[shader_dsl::shader(
//!     axes(msaa: u32 = [1, 4]),
//!     uses(
//!         crate::normals_again,
//!         shaders_gen::shared::pbr,
//!         shaders_gen::deferred::gbuffer_read::tbdr_gbuffer,
//!         shaders_gen::shared::light_grid,
//!     ),
//! )]
//! pub mod engine_pass {
//!     #[storage(group = 1, binding = 0, read_write)]
//!     static OUT: [Vec4];
//!     #[storage(group = 1, binding = 1)]
//!     static LIGHTS_IN: [GpuLight];
//!
//!     #[compute(workgroup_size(8, 8, 1))]
//!     fn main(#[builtin(global_invocation_id)] gid: UVec3) {
//!         let s = centre_shading(gid.xy(), load_sample(gid.xy(), 0u32)).point;
//!         let n = round_trip(s.n);
//!         let c = shade_light(LIGHTS_IN[0], s.p, n, s.v, s.albedo, s.metallic, s.roughness);
//!         OUT[gid.y * 8u32 + gid.x] = c.extend(1.0);
//!     }
//! }
//!
//! fn main() {
//!     // The host types are `shaders_gen`'s own, re-exported: one Rust type, not a copy.
//!     let light: engine_pass::GpuLight = shaders_gen::shared::pbr::GpuLight::default();
//!     assert_eq!(light.intensity, 0.0);
//!     let _: Option<engine_pass::TbdrParams> =
//!         None::<shaders_gen::deferred::gbuffer_read::tbdr_gbuffer::TbdrParams>;
//!     assert_eq!(engine_pass::VARIANTS.len(), 2);
//!     for v in engine_pass::VARIANTS {
//!         assert!(v.wgsl.contains("fn octahedral_decode("));
//!         assert!(v.wgsl.contains("fn shade_light("));
//!         // `dither_noise` comes from the shadow-atlas library, which only the G-buffer
//!         // library names.
//!         assert!(v.wgsl.contains("fn dither_noise("));
//!     }
//! }
//! ```

pub mod append;
pub mod atlas;
pub mod brdf;
pub mod camera;
pub mod decal;
pub mod frustum;
pub mod grid;
pub mod lights;
pub mod material;
pub mod normals;
pub mod samples;
pub mod shadow;

pub use append::cull_append;
pub use atlas::material_atlas;
pub use brdf::pbr;
pub use camera::view;
pub use decal::decal_apply;
pub use frustum::box_frustum;
pub use grid::light_grid;
pub use lights::{light_lists, light_set, light_spheres, surface_light};
pub use material::{material_table, material_uv};
pub use normals::octahedral;
pub use samples::sample_pattern;
pub use shadow::shadow_atlas;
