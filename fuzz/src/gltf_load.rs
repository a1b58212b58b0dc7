//! glTF bytes → scene load → GPU upload preparation, all on the CPU.
//!
//! The bytes are loaded as a self-contained scene ([`Scene::from_slice`]: a GLB, or a `.gltf`
//! with `data:` URIs). A scene that loads is checked against WebGPU's default limits (what
//! `Renderer::prepare_scene` checks against the device's) and, when it fits, prepared as the
//! renderer would before allocating: the draw list with its uniforms and each material texture's coordinates.
//! Any error must be a `SceneError` with a message; the prepared data must be consistent with
//! the scene.

use renderer::frame_data::{DEFAULT_LIGHT_CUTOFF, draw_plan, uv_map, with_effective_ranges};
use renderer::scene::Scene;

/// Loads and prepares `data`. Panics only on a broken contract.
pub fn run(data: &[u8]) {
    let scene = match Scene::from_slice(data) {
        Ok(scene) => scene,
        Err(e) => {
            assert!(!e.to_string().is_empty());
            return;
        }
    };
    if let Err(e) = scene.check_for_device(&wgpu::Limits::default()) {
        assert!(!e.to_string().is_empty());
        return;
    }
    for w in &scene.warnings {
        assert!(!w.to_string().is_empty());
    }
    let default_material = scene.materials.len();
    let draws = draw_plan(&scene);
    let primitives: usize = scene
        .instances
        .iter()
        .map(|i| scene.meshes[i.mesh].primitives.len())
        .sum();
    assert_eq!(
        draws.len(),
        primitives,
        "one draw per primitive of each instance"
    );
    for d in &draws {
        assert!(d.material <= default_material);
        assert!(d.instance < scene.instances.len());
    }
    for m in &scene.materials {
        for t in [
            m.base_color_texture,
            m.normal_texture,
            m.metallic_roughness_texture,
            m.occlusion_texture,
            m.emissive_texture,
        ] {
            let _ = uv_map(t);
        }
    }
    let _ = scene.triangle_count();
    for light in with_effective_ranges(&scene.lights, DEFAULT_LIGHT_CUTOFF) {
        if let Some(r) = light.range {
            assert!(!r.is_nan(), "a light's range is NaN");
        }
    }
}
