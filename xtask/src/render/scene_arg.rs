//! What a tool's `--scene` opens: a built-in scene by name (`courtyard`, `city:N`) or a glTF
//! file, with where procedural lights go in it, and the camera it is seen from.

use std::path::Path;

use anyhow::{Context as _, Result, bail};
use glam::Vec3;
use renderer::demo::light_space;
use renderer::frame::FrameCamera;
use renderer::frame::{camera_of, default_camera, scene_camera};
use renderer::scene::procedural::{BuiltinScene, builtin};
use renderer::scene::{Aabb, Scene};

/// The `--scene` name of the built-in scene.
pub const BUILTIN_SCENE: &str = "courtyard";

/// A scene a tool opened.
pub struct OpenedScene {
    pub scene: Scene,
    /// The file, or the built-in scene's name.
    pub name: String,
    pub light_region: Aabb,
    pub light_radii: (f32, f32),
    /// The courtyard, which has its own look.
    pub courtyard: bool,
    /// A generated scene (`city:N`): its bounds grow with its size, its lit region does not,
    /// so lights that must stay comparable across sizes go in `light_region`.
    pub generated: bool,
}

/// Opens `arg`: none or `courtyard` is the built-in courtyard, `city:N` a generated city, and
/// anything else a `.gltf` or `.glb` file (its warnings printed).
pub fn open_scene(arg: Option<&Path>) -> Result<OpenedScene> {
    let name = arg.map_or(BUILTIN_SCENE.into(), |p| p.to_string_lossy().into_owned());
    if let Some(b) = builtin(&name).map_err(|e| anyhow::anyhow!("--scene {e}"))? {
        let BuiltinScene {
            scene,
            light_region,
            light_radii,
            courtyard,
        } = b;
        return Ok(OpenedScene {
            scene,
            name,
            light_region,
            light_radii,
            courtyard,
            generated: !courtyard,
        });
    }
    let path = Path::new(&name);
    if !path.is_file() {
        bail!(
            "--scene {name}: no such file (give a .gltf or .glb file, {}, or city:N for a \
             generated city of N instances)",
            BUILTIN_SCENE
        );
    }
    let scene = Scene::load(path).with_context(|| format!("--scene {name}: cannot load it"))?;
    for warning in &scene.warnings {
        eprintln!("warning: {name}: {warning}");
    }
    let (light_region, light_radii) = light_space(&scene, false);
    Ok(OpenedScene {
        scene,
        name,
        light_region,
        light_radii,
        courtyard: false,
        generated: false,
    })
}

/// The frame's camera: the scene's camera `--camera i`, one from `--eye`/`--target`, or a
/// framing default.
pub(super) fn pick_camera(
    (camera, eye, target): (Option<usize>, Option<Vec3>, Option<Vec3>),
    scene: &Scene,
    aspect: f32,
) -> Result<FrameCamera> {
    if let Some(i) = camera {
        return camera_of(scene, i, aspect).ok_or_else(|| {
            anyhow::anyhow!(
                "--camera {i}: the scene has {} camera(s)",
                scene.cameras.len()
            )
        });
    }
    if let (Some(eye), Some(target)) = (eye, target) {
        let size = (scene.bounds.max - scene.bounds.min).length().max(1e-3);
        let (near, far) = (size * 0.01, size * 10.0);
        let world_from_view = glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y).inverse();
        return Ok(scene_camera(
            world_from_view,
            45f32.to_radians(),
            aspect,
            near,
            far,
        ));
    }
    Ok(default_camera(scene, aspect))
}
