//! A fly camera: position, yaw and pitch, moved by WASD/QE and turned by mouse drags, at a fixed
//! speed per second (scripted runs use a fixed time step, so they are reproducible).

use glam::{Mat4, Vec3};
use renderer::frame::FrameCamera;
use renderer::frame::scene_camera;

/// Metres per second.
pub const SPEED: f32 = 4.0;
/// Radians per pixel of mouse drag.
pub const TURN: f32 = 0.004;

/// Where the camera is and where it looks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fly {
    pub eye: Vec3,
    /// Radians about +Y; 0 looks down −Z.
    pub yaw: f32,
    /// Radians up from the horizon, within ±89°.
    pub pitch: f32,
    /// Vertical field of view, radians.
    pub yfov: f32,
}

/// Movement keys held during one frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Held {
    pub forward: bool,
    pub back: bool,
    pub left: bool,
    pub right: bool,
    pub up: bool,
    pub down: bool,
}

impl Fly {
    /// The camera looking from `eye` at `target`.
    pub fn looking_at(eye: Vec3, target: Vec3, yfov: f32) -> Fly {
        let d = (target - eye).normalize_or(Vec3::NEG_Z);
        Fly {
            eye,
            yaw: (-d.x).atan2(-d.z),
            pitch: d.y.clamp(-1.0, 1.0).asin(),
            yfov,
        }
    }

    /// From a scene camera's world-from-view matrix.
    pub fn from_world_from_view(world_from_view: Mat4, yfov: f32) -> Fly {
        let eye = world_from_view.w_axis.truncate();
        let ahead = -world_from_view.z_axis.truncate();
        Fly::looking_at(eye, eye + ahead, yfov)
    }

    /// Unit view direction.
    pub fn forward(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        Vec3::new(-sy * cp, sp, -cy * cp)
    }

    /// Moves for `dt` seconds with `held` keys.
    pub fn step(&mut self, held: Held, dt: f32) {
        let f = self.forward();
        let right = f.cross(Vec3::Y).normalize_or(Vec3::X);
        let axis = |a: bool, b: bool| f32::from(u8::from(a)) - f32::from(u8::from(b));
        let v = f * axis(held.forward, held.back)
            + right * axis(held.right, held.left)
            + Vec3::Y * axis(held.up, held.down);
        self.eye += v * SPEED * dt;
    }

    /// Turns by a mouse drag of `(dx, dy)` pixels.
    pub fn turn(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * TURN;
        self.pitch = (self.pitch - dy * TURN).clamp(-89f32.to_radians(), 89f32.to_radians());
    }

    /// The renderer's camera for an `aspect` (width / height) viewport.
    pub fn camera(&self, aspect: f32) -> FrameCamera {
        let world_from_view =
            glam::camera::rh::view::look_at_mat4(self.eye, self.eye + self.forward(), Vec3::Y)
                .inverse();
        scene_camera(world_from_view, self.yfov, aspect, 0.1, 200.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn looking_at_a_target_faces_it_and_forward_moves_towards_it() {
        let mut fly = Fly::looking_at(Vec3::new(0.0, 1.0, 5.0), Vec3::new(3.0, 1.0, 1.0), 1.0);
        let d = fly.forward();
        assert!((d - Vec3::new(0.6, 0.0, -0.8)).length() < 1e-5, "{d}");
        let held = Held {
            forward: true,
            ..Held::default()
        };
        fly.step(held, 0.25);
        assert!(
            (fly.eye - Vec3::new(0.6, 1.0, 4.2)).length() < 1e-5,
            "{}",
            fly.eye
        );
        fly.turn(0.0, -1e6);
        assert!(fly.pitch <= 89f32.to_radians());
    }
}
