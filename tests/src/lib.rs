//! Workspace-level integration tests: GPU tests under validation, CPU references, image tests and
//! codegen snapshots.
//!
//! This library holds the shared harness; the tests themselves are in `tests/tests/`. Every GPU
//! test gets its device from [`gpu::gpu_test`], which fails loudly when there is no adapter or no
//! validation layer, and fails the test on any validation error it caused.

pub mod browser;
pub mod cull_interp;
pub mod cull_run;
pub mod cull_scene;
pub mod decal_letters;
pub mod decal_stage;
pub mod depth_upload;
pub mod dsl_fuzz;
pub mod frame_probe;
pub mod frames;
pub mod gpu;
pub mod host_replay;
pub mod image_compare;
pub mod materials;
pub mod particle_atlas_probe;
pub mod particle_light_interp;
pub mod particle_light_reference;
pub mod particle_stage;
pub mod process_memory;
pub mod shadow_bounds;
pub mod shadow_probe;
pub mod shadow_scene;
pub mod tbdr_interp;
pub mod tbdr_stage;
