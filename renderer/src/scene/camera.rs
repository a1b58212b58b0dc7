//! Cameras from the file: perspective and orthographic projections, as glTF 2.0 defines them.

use glam::Mat4;

/// A camera from the file, placed in the world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SceneCamera {
    /// The camera node's world transform; the view looks down its −Z with +Y up (glTF).
    pub world_from_view: Mat4,
    /// How view space maps to the image.
    pub projection: CameraProjection,
}

/// A file camera's projection (glTF `camera.perspective` or `camera.orthographic`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CameraProjection {
    /// Vertical field of view `yfov` (radians), the file's aspect ratio if it gives one, and
    /// the near and (optional: infinite) far planes.
    Perspective {
        /// Vertical field of view, radians.
        yfov: f32,
        /// Width over height; the renderer draws at the viewport's aspect instead.
        aspect: Option<f32>,
        /// Near plane distance, view units (metres).
        znear: f32,
        /// Far plane distance; `None`: infinite.
        zfar: Option<f32>,
    },
    /// Half the view's width (`xmag`) and height (`ymag`) in view units, and the near and far
    /// planes (glTF requires both).
    Orthographic {
        /// Half the view's width.
        xmag: f32,
        /// Half the view's height.
        ymag: f32,
        /// Near plane distance.
        znear: f32,
        /// Far plane distance.
        zfar: f32,
    },
}

impl CameraProjection {
    /// The near plane's distance.
    pub fn znear(&self) -> f32 {
        match *self {
            Self::Perspective { znear, .. } | Self::Orthographic { znear, .. } => znear,
        }
    }

    /// The far plane's distance (`None`: an infinite perspective projection).
    pub fn zfar(&self) -> Option<f32> {
        match *self {
            Self::Perspective { zfar, .. } => zfar,
            Self::Orthographic { zfar, .. } => Some(zfar),
        }
    }
}

/// The scene camera of `camera` placed at `world`.
#[cfg(feature = "gltf")]
pub(super) fn camera_of(camera: &gltf::Camera<'_>, world: Mat4) -> SceneCamera {
    let projection = match camera.projection() {
        gltf::camera::Projection::Perspective(p) => CameraProjection::Perspective {
            yfov: p.yfov(),
            aspect: p.aspect_ratio(),
            znear: p.znear(),
            zfar: p.zfar(),
        },
        gltf::camera::Projection::Orthographic(o) => CameraProjection::Orthographic {
            xmag: o.xmag(),
            ymag: o.ymag(),
            znear: o.znear(),
            zfar: o.zfar(),
        },
    };
    SceneCamera {
        world_from_view: world,
        projection,
    }
}
