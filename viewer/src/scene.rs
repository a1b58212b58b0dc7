//! What the viewer shows: the built-in courtyard (or a glTF file) with seeded procedural lights,
//! its look (exposure, ambient, sky) and the camera it starts from; built the same way by the
//! window and by headless checks.

use std::path::Path;

use anyhow::{Context as _, Result};
use renderer::frame::RendererConfig;
use renderer::frame::setup::procedural_lights;
use renderer::scene::procedural::{
    COURTYARD_AMBIENT, COURTYARD_EV, COURTYARD_LIGHT_RADII, COURTYARD_LIGHT_REGION, COURTYARD_SKY,
    courtyard,
};
use renderer::scene::{Aabb, Scene, SceneLight};

use crate::fly::Fly;

/// A scene, its lights and the camera to start from.
#[derive(Debug)]
pub struct Shown {
    pub scene: Scene,
    pub lights: Vec<SceneLight>,
    pub start: Fly,
    /// Where procedural lights go, their radii and seed.
    pub light_region: Aabb,
    pub light_radii: (f32, f32),
    pub seed: u64,
    /// The built-in courtyard (which has its own look).
    pub builtin: bool,
}

/// The courtyard (`file == None`) or a glTF file, with `count` lights of `seed`.
pub fn load(file: Option<&Path>, count: usize, seed: u64) -> Result<Shown> {
    let (scene, light_region, light_radii) = match file {
        None => (courtyard(), COURTYARD_LIGHT_REGION, COURTYARD_LIGHT_RADII),
        Some(path) => {
            let scene = Scene::load(path)
                .with_context(|| format!("--scene {}: cannot load it", path.display()))?;
            let size = (scene.bounds.max - scene.bounds.min).length();
            let bounds = scene.bounds;
            (scene, bounds, (size * 0.03, size * 0.2))
        }
    };
    let start = match scene.cameras.first() {
        Some(c) => Fly::from_world_from_view(c.world_from_view, c.yfov),
        None => {
            let b = scene.bounds;
            let size = (b.max - b.min).length().max(1e-3);
            Fly::looking_at(
                b.center() + glam::Vec3::new(0.0, 0.35, 1.0).normalize() * size,
                b.center(),
                45f32.to_radians(),
            )
        }
    };
    let mut shown = Shown {
        scene,
        lights: vec![],
        start,
        light_region,
        light_radii,
        seed,
        builtin: file.is_none(),
    };
    shown.lights = procedural(&shown, count);
    Ok(shown)
}

/// The scene's own lights and `count` procedural ones.
pub fn procedural(shown: &Shown, count: usize) -> Vec<SceneLight> {
    let mut lights = shown.scene.lights.clone();
    let (min, max) = shown.light_radii;
    lights.extend(procedural_lights(
        shown.light_region,
        count,
        shown.seed,
        min,
        max,
    ));
    lights
}

/// The renderer settings of the scene's look: the courtyard's exposure, ambient and sky, or the
/// defaults for a file.
pub fn look(shown: &Shown) -> RendererConfig {
    if !shown.builtin {
        return RendererConfig::default();
    }
    RendererConfig {
        exposure: 2f32.powf(COURTYARD_EV),
        ambient: COURTYARD_AMBIENT,
        sky: COURTYARD_SKY,
        ..RendererConfig::default()
    }
}
