//! The cameras a scene opens on (its own, or one that frames it) and a target texture to draw a
//! frame into: helpers for engines and tools that show a loaded scene.

use glam::{Mat4, Vec3, camera::rh};

use super::{FrameCamera, RendererConfig};
use crate::scene::{Aabb, CameraProjection, Scene};

/// A perspective camera looking at the centre of `bounds` from the front and a little above.
pub fn framing_camera(bounds: Aabb, aspect: f32) -> FrameCamera {
    let center = bounds.center();
    let radius = ((bounds.max - bounds.min).length() * 0.5).max(1e-3);
    let eye = center + Vec3::new(0.0, 0.35, 1.0).normalize() * radius * 2.4;
    FrameCamera::look_at(
        eye,
        center,
        Vec3::Y,
        FRAMING_YFOV_DEGREES.to_radians(),
        aspect,
        (radius * 0.05, radius * 8.0),
    )
}

/// The field of view of [`framing_camera`].
pub const FRAMING_YFOV_DEGREES: f32 = 45.0;

/// The scene's camera `index`: a perspective camera at the viewport's `aspect` (its far plane,
/// or ten scene sizes where the file sets none), an orthographic one with the file's `xmag` and
/// `ymag` as they are (glTF's orthographic matrix: a viewport of another aspect stretches it).
pub fn camera_of(scene: &Scene, index: usize, aspect: f32) -> Option<FrameCamera> {
    let size = (scene.bounds.max - scene.bounds.min).length().max(1e-3);
    scene.cameras.get(index).map(|c| match c.projection {
        CameraProjection::Perspective {
            yfov, znear, zfar, ..
        } => scene_camera(
            c.world_from_view,
            yfov,
            aspect,
            znear,
            zfar.unwrap_or(size * 10.0),
        ),
        CameraProjection::Orthographic {
            xmag,
            ymag,
            znear,
            zfar,
        } => FrameCamera::orthographic(c.world_from_view, (xmag, ymag), (znear, zfar)),
    })
}

/// The scene's first camera, else [`framing_camera`]: what tools open a scene on.
pub fn default_camera(scene: &Scene, aspect: f32) -> FrameCamera {
    camera_of(scene, 0, aspect).unwrap_or_else(|| framing_camera(scene.bounds, aspect))
}

/// A perspective camera placed by `world_from_view` (a glTF node's transform), with vertical
/// field of view `yfov`.
pub fn scene_camera(
    world_from_view: Mat4,
    yfov: f32,
    aspect: f32,
    near: f32,
    far: f32,
) -> FrameCamera {
    FrameCamera {
        view: world_from_view.inverse(),
        projection: rh::proj::directx::perspective(yfov, aspect, near, far),
        eye: world_from_view.transform_point3(Vec3::ZERO),
        near,
        far,
        orthographic: false,
    }
}

/// A texture the renderer can draw a frame into (`config.output_format`, the configured size),
/// readable back with [`crate::readback::read_texture_rgba8`].
///
/// It is a render attachment and takes copies. Where the compute tonemap serves the output
/// format ([`RendererConfig::compute_tonemap`], `Rgba8Unorm` or `Rgba8UnormSrgb`), it is also a
/// storage image, which the kernel writes without a copy: an `Rgba8UnormSrgb` output is then
/// stored as `Rgba8Unorm` with `Rgba8UnormSrgb` among its view formats (a storage image
/// cannot be sRGB), and holds the same sRGB-encoded bytes. View it as
/// `config.output_format` to sample or display it as sRGB.
pub fn create_target(device: &wgpu::Device, config: &RendererConfig) -> wgpu::Texture {
    let storage = config.compute_tonemap
        && config.output_format.remove_srgb_suffix() == wgpu::TextureFormat::Rgba8Unorm;
    let (format, storage_usage) = if storage {
        (
            wgpu::TextureFormat::Rgba8Unorm,
            wgpu::TextureUsages::STORAGE_BINDING,
        )
    } else {
        (config.output_format, wgpu::TextureUsages::empty())
    };
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("frame target"),
        size: wgpu::Extent3d {
            width: config.width,
            height: config.height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST
            | storage_usage,
        view_formats: if format == config.output_format {
            &[]
        } else {
            std::slice::from_ref(&config.output_format)
        },
    })
}
