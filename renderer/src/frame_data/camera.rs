//! The camera of a frame, and the uniform buffer that holds it for every pass that draws.

use shaders_gen::forward::forward;

/// The camera of a frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameCamera {
    pub view: glam::Mat4,
    /// A wgpu (depth 0..1) perspective projection.
    pub projection: glam::Mat4,
    pub eye: glam::Vec3,
    pub near: f32,
    pub far: f32,
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
        }
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
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
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
        );
        queue.write_buffer(&self.buffer, 0, bytemuck::bytes_of(&uniform));
    }
}
