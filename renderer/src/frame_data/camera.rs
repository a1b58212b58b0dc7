//! The camera of a frame, and the uniform buffer that holds it for every pass that draws.

use shaders_gen::forward::forward;

/// The camera of a frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameCamera {
    /// View from world: right-handed, the camera looking down its −Z axis.
    pub view: glam::Mat4,
    /// A wgpu (depth 0..1) projection: perspective, or orthographic when `orthographic`.
    pub projection: glam::Mat4,
    /// The camera's position (an orthographic camera's too, though its view rays are parallel).
    pub eye: glam::Vec3,
    /// Distance to the near plane, in world units (view depth where the projection gives 0).
    pub near: f32,
    /// Distance to the far plane, in world units (view depth where the projection gives 1).
    pub far: f32,
    /// Whether `projection` is orthographic: view rays run parallel to the view's −Z axis, view
    /// depth no longer scales screen size, and the direction towards the eye is the view's +Z
    /// axis everywhere ([`FrameCamera::eye_homogeneous`]).
    pub orthographic: bool,
}

impl FrameCamera {
    /// A perspective camera at `eye` looking at `target`, `up` roughly up, with a vertical field
    /// of view of `yfov` radians, an `aspect` (width / height) and wgpu depth from `near` to
    /// `far`.
    pub fn look_at(
        eye: glam::Vec3,
        target: glam::Vec3,
        up: glam::Vec3,
        yfov: f32,
        aspect: f32,
        (near, far): (f32, f32),
    ) -> Self {
        use glam::camera::rh;
        Self {
            view: rh::view::look_at_mat4(eye, target, up),
            projection: rh::proj::directx::perspective(yfov, aspect, near, far),
            eye,
            near,
            far,
            orthographic: false,
        }
    }

    /// An orthographic camera placed by `world_from_view`, seeing `half_width` × `half_height`
    /// view units either side of its axis, with wgpu depth from `near` to `far` (glTF's
    /// `xmag`, `ymag`, `znear`, `zfar`).
    pub fn orthographic(
        world_from_view: glam::Mat4,
        (half_width, half_height): (f32, f32),
        (near, far): (f32, f32),
    ) -> Self {
        use glam::camera::rh;
        Self {
            view: world_from_view.inverse(),
            projection: rh::proj::directx::orthographic(
                -half_width,
                half_width,
                -half_height,
                half_height,
                near,
                far,
            ),
            eye: world_from_view.transform_point3(glam::Vec3::ZERO),
            near,
            far,
            orthographic: true,
        }
    }

    /// Where view vectors point, homogeneous: `(eye, 1)` for a perspective camera, so the view
    /// vector at `p` is `eye − p`; `(+Z axis of the view in world space, 0)`, a point at infinity,
    /// for an orthographic one, whose view vector is that axis at every point.
    pub fn eye_homogeneous(&self) -> glam::Vec4 {
        if self.orthographic {
            let back = self.view.inverse().transform_vector3(glam::Vec3::Z);
            back.normalize_or_zero().extend(0.0)
        } else {
            self.eye.extend(1.0)
        }
    }

    /// The six planes of the view frustum (`frustum_planes` of view-projection).
    pub fn frustum_planes(&self) -> [glam::Vec4; 6] {
        frustum_planes(self.projection * self.view)
    }
}

/// The six planes of `view_projection` (wgpu depth 0..1), inside where `dot(xyz, p) + w >= 0`,
/// normalised; a degenerate plane (an infinite far plane) keeps everything.
pub fn frustum_planes(view_projection: glam::Mat4) -> [glam::Vec4; 6] {
    let m = view_projection.as_dmat4();
    let row = |i: usize| glam::DVec4::new(m.x_axis[i], m.y_axis[i], m.z_axis[i], m.w_axis[i]);
    let (r0, r1, r2, r3) = (row(0), row(1), row(2), row(3));
    [r3 + r0, r3 - r0, r3 + r1, r3 - r1, r2, r3 - r2].map(|p| {
        let length = p.truncate().length();
        if length < 1e-12 {
            glam::Vec4::W
        } else {
            (p / length).as_vec4()
        }
    })
}

/// Whether `b` reaches the inner side of every plane of `planes` (tested at its corner furthest
/// along each plane's normal), `slack` world units outside counting as inside. An empty box is
/// kept.
pub fn box_in_frustum(planes: &[glam::Vec4; 6], b: crate::scene::Aabb, slack: f32) -> bool {
    b.is_empty()
        || planes.iter().all(|q| {
            let corner = glam::Vec3::select(q.truncate().cmpge(glam::Vec3::ZERO), b.max, b.min);
            q.truncate().dot(corner) + q.w >= -slack
        })
}

/// How far `p` lies from the camera whose homogeneous eye is `eye` (see
/// [`FrameCamera::eye_homogeneous`]), for back-to-front order: the squared distance from a
/// perspective camera's eye; an orthographic camera's rays are parallel, so its depth along
/// them (`−p · axis`, up to a constant).
pub fn farness(eye: glam::Vec4, p: glam::Vec3) -> f32 {
    if eye.w == 0.0 {
        -p.dot(eye.truncate())
    } else {
        p.distance_squared(eye.truncate() / eye.w)
    }
}

/// The camera uniform (`Camera` of the pre-Z and forward programs), rewritten each frame.
#[derive(Debug, Clone)]
pub struct CameraUniform {
    pub buffer: wgpu::Buffer,
}

impl CameraUniform {
    pub fn new(device: &wgpu::Device) -> Self {
        Self {
            buffer: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("camera"),
                size: size_of::<forward::Camera>() as u64,
                // COPY_SRC: tools read back what a kernel bound (the tests' host replay).
                usage: wgpu::BufferUsages::UNIFORM
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
        }
    }

    /// Writes `camera` for the next submission.
    pub fn write(&self, queue: &wgpu::Queue, camera: &FrameCamera) {
        let uniform = forward::Camera::new(
            camera.view,
            camera.projection,
            camera.projection * camera.view,
            camera.eye,
            camera.eye_homogeneous(),
        );
        queue.write_buffer(&self.buffer, 0, bytemuck::bytes_of(&uniform));
    }
}

#[cfg(test)]
#[path = "camera_tests.rs"]
mod tests;
