//! Cameras from the file.

use glam::Mat4;

/// A perspective camera from the file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SceneCamera {
    pub world_from_view: Mat4,
    pub yfov: f32,
    pub aspect: Option<f32>,
    pub znear: f32,
    pub zfar: Option<f32>,
}

/// The scene camera of `camera` placed at `world`, or `None` where its projection is not
/// supported.
pub(super) fn camera_of(camera: &gltf::Camera<'_>, world: Mat4) -> Option<SceneCamera> {
    match camera.projection() {
        gltf::camera::Projection::Perspective(p) => Some(SceneCamera {
            world_from_view: world,
            yfov: p.yfov(),
            aspect: p.aspect_ratio(),
            znear: p.znear(),
            zfar: p.zfar(),
        }),
        gltf::camera::Projection::Orthographic(_) => None,
    }
}
