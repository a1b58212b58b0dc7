//! What the viewer shows: the built-in courtyard (or a generated city, `city:N`, or a glTF
//! file) with seeded procedural lights, decals and particles, its look (exposure, ambient,
//! sky) and the camera it starts from; built the same way by the window and by headless
//! checks.

use std::path::Path;

use anyhow::{Context as _, Result};
use renderer::decals::{DecalSet, procedural};
use renderer::demo::scatter_decals;
use renderer::demo::{courtyard_look, light_space, pick_shadowed, procedural_lights};
use renderer::frame::RendererConfig;
use renderer::frame::{FRAMING_YFOV_DEGREES, default_camera};
use renderer::particles::{ParticleSystem, builtin_system};
use renderer::scene::{Aabb, CameraProjection, Scene, SceneLight};

use crate::fly::Fly;

/// A scene, its lights and the camera to start from.
#[derive(Debug)]
pub struct Shown {
    pub scene: Scene,
    pub lights: Vec<SceneLight>,
    /// Procedural decals (built-in materials) on the scene's surfaces.
    pub decals: DecalSet,
    /// The built-in smoke, sparks and dust (none for `--particles 0`).
    pub particles: Option<ParticleSystem>,
    pub start: Fly,
    /// Where procedural lights go, their radii and seed.
    pub light_region: Aabb,
    pub light_radii: (f32, f32),
    pub seed: u64,
    /// The built-in courtyard (which has its own look).
    pub builtin: bool,
}

/// The courtyard (`file == None` or `courtyard`), a generated city (`city:N`) or a glTF file, with `count` lights, `decals` decals and
/// about `particles` particles of `seed`.
pub fn load(
    file: Option<&Path>,
    count: usize,
    decals: usize,
    particles: u32,
    seed: u64,
) -> Result<Shown> {
    let name = file.map_or("courtyard".into(), |p| p.to_string_lossy().into_owned());
    let builtin =
        renderer::scene::procedural::builtin(&name).map_err(|e| anyhow::anyhow!("--scene {e}"))?;
    let (scene, (light_region, light_radii), courtyard) = match builtin {
        Some(b) => (b.scene, (b.light_region, b.light_radii), b.courtyard),
        None => {
            let path = Path::new(&name);
            let scene = Scene::load(path)
                .with_context(|| format!("--scene {}: cannot load it", path.display()))?;
            for warning in &scene.warnings {
                eprintln!("warning: {}: {warning}", path.display());
            }
            let space = light_space(&scene, false);
            (scene, space, false)
        }
    };
    // The camera the renderer's tools open on (the scene's own, else one framing it). The fly
    // camera is perspective: on an orthographic file camera it starts at that camera's pose
    // with the framing camera's field of view.
    let opening = default_camera(&scene, 1.0);
    let yfov = match scene.cameras.first().map(|c| c.projection) {
        Some(CameraProjection::Perspective { yfov, .. }) => yfov,
        Some(CameraProjection::Orthographic { .. }) | None => FRAMING_YFOV_DEGREES.to_radians(),
    };
    let start = Fly::from_world_from_view(opening.view.inverse(), yfov);
    let materials = procedural::materials();
    let placed = scatter_decals(&scene, decals, materials.len(), seed);
    let particles = (particles > 0).then(|| builtin_system(scene.bounds, particles, seed as u32));
    let mut shown = Shown {
        particles,
        decals: DecalSet {
            materials,
            decals: placed,
        },
        scene,
        lights: vec![],
        start,
        light_region,
        light_radii,
        seed,
        builtin: courtyard,
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
    // The lights that matter most from the starting camera cast shadows.
    let camera = default_camera(&shown.scene, 16.0 / 9.0);
    let first = shown.scene.lights.len();
    pick_shadowed(&mut lights[first..], &camera, 720.0, SHADOWED_LIGHTS);
    lights
}

/// Procedural lights that cast shadows in the viewer.
pub const SHADOWED_LIGHTS: usize = 16;

/// The renderer settings of the scene's look: the courtyard's exposure, ambient and sky, or the
/// defaults for a file.
pub fn look(shown: &Shown) -> RendererConfig {
    if shown.builtin {
        courtyard_look(RendererConfig::default())
    } else {
        RendererConfig::default()
    }
}
