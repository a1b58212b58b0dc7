//! The project's own GPU code, written once in the shader DSL: the light-culling kernels, the
//! pre-Z, forward, tonemap and heatmap shaders, and small tool kernels, each exposing every
//! generated variant. Code several modules need (camera and clip position, light-grid lookups,
//! the culling list append, the BRDF) is written once in the libraries of [`shared`].
//!
//! Each module here is a `#[shader_dsl::shader]` module: at compile time it becomes WGSL and
//! SPIR-V for every variant (validated by naga), host structs with the WGSL layout, a typed
//! `VariantKey` and a `variant(key)` lookup. The renderer takes all of its shader code from
//! here. [`MODULES`] lists every module, for tools such as `cargo xtask shaders`.

pub mod bootstrap;
pub mod calibrate;
pub mod culling;
pub mod deferred;
pub mod forward;
pub mod inspect;
pub mod particles;
pub mod shadow;
pub mod shared;
pub mod visibility;

/// Every generated module, for tools that walk them all.
pub static MODULES: &[&codegen::rt::Module] = &[
    &bootstrap::test_pattern::MODULE,
    &bootstrap::square_plus_index::MODULE,
    &calibrate::fma_rate::MODULE,
    &culling::cull_prepare::MODULE,
    &culling::tile_cull::MODULE,
    &culling::cluster_cull::MODULE,
    &culling::instance_cull::MODULE,
    &culling::draw_compact::MODULE,
    &culling::blended_order::MODULE,
    &culling::depth_pyramid_seed::MODULE,
    &culling::depth_pyramid_reduce::MODULE,
    &culling::occlusion_cull::MODULE,
    &deferred::hdr_overlay::MODULE,
    &deferred::overlay_erase::MODULE,
    &deferred::tbdr::MODULE,
    &deferred::light_volume::MODULE,
    &forward::prez::MODULE,
    &forward::forward::MODULE,
    &forward::heatmap::MODULE,
    &forward::tonemap::MODULE,
    &forward::tonemap_compute::MODULE,
    &inspect::depth_probe::MODULE,
    &inspect::sample_copy::MODULE,
    &particles::particle_atlas::MODULE,
    &particles::particle_draw::MODULE,
    &particles::particle_light::MODULE,
    &particles::particle_sim::MODULE,
    &particles::particle_sort::MODULE,
    &shadow::shadow_atlas_view::MODULE,
    &shadow::shadow_caster::MODULE,
    &shadow::shadow_compose::MODULE,
    &shadow::shadow_cull::MODULE,
    &visibility::vis_raster::MODULE,
    &visibility::vis_compute_raster::MODULE,
    &visibility::vis_resolve::MODULE,
];
