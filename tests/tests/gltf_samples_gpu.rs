//! Khronos's glTF sample models (committed under `tests/scenes`, each with its licence), rendered
//! and checked where the glTF rule each one exercises would show if it were broken: pixel colours
//! where the model's README says what must show, or a node against its unmirrored twin. Culled
//! paths agreeing with naive forward cannot catch these; each check here compares with what the
//! specification says.
//!
//! One module per rule; helpers they share live here.

use std::path::{Path, PathBuf};

use renderer::scene::Scene;

/// The committed sample model `relative` (below `tests/scenes`).
pub fn sample_path(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(relative)
}

/// Loads the committed sample model `relative` (below `tests/scenes`), failing the test with
/// the loader's message if it is refused.
pub fn sample(relative: &str) -> Scene {
    let path = sample_path(relative);
    Scene::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}
#[path = "gltf_samples_gpu/cameras.rs"]
mod cameras;
#[path = "gltf_samples_gpu/default_ambient.rs"]
mod default_ambient;
#[path = "gltf_samples_gpu/material_inputs.rs"]
mod material_inputs;
#[path = "gltf_samples_gpu/material_models.rs"]
mod material_models;
#[path = "gltf_samples_gpu/material_shadows.rs"]
mod material_shadows;
#[path = "gltf_samples_gpu/negative_scale.rs"]
mod negative_scale;
#[path = "gltf_samples_gpu/quads.rs"]
mod quads;
#[path = "gltf_samples_gpu/tbdr_thin.rs"]
mod tbdr_thin;
