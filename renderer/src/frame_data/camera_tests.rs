//! The orthographic camera: its projection, its view vector and its back-to-front order.

use glam::{Mat4, Vec3, Vec4};

use super::*;

/// An orthographic camera at `(0, 0, 10)` looking down −Z, seeing ±4 × ±2 units.
fn ortho() -> FrameCamera {
    FrameCamera::orthographic(
        Mat4::from_translation(Vec3::new(0.0, 0.0, 10.0)),
        (4.0, 2.0),
        (1.0, 21.0),
    )
}

#[test]
fn an_orthographic_camera_maps_its_box_to_wgpu_clip_space() {
    let c = ortho();
    let clip = |p: Vec3| c.projection * c.view * p.extend(1.0);
    // The near plane's corner and the far plane's opposite corner.
    assert!(clip(Vec3::new(-4.0, -2.0, 9.0)).abs_diff_eq(Vec4::new(-1.0, -1.0, 0.0, 1.0), 1e-5));
    assert!(clip(Vec3::new(4.0, 2.0, -11.0)).abs_diff_eq(Vec4::new(1.0, 1.0, 1.0, 1.0), 1e-5));
    assert!(c.orthographic);
    assert_eq!(c.eye, Vec3::new(0.0, 0.0, 10.0));
}

#[test]
fn the_view_vector_is_the_axis_for_orthographic_and_the_eye_for_perspective() {
    assert!(
        ortho()
            .eye_homogeneous()
            .abs_diff_eq(Vec4::new(0.0, 0.0, 1.0, 0.0), 1e-6)
    );
    let eye = Vec3::new(1.0, 2.0, 3.0);
    let p = FrameCamera::look_at(eye, Vec3::ZERO, Vec3::Y, 1.0, 1.0, (0.1, 10.0));
    assert_eq!(p.eye_homogeneous(), eye.extend(1.0));
}

#[test]
fn back_to_front_follows_depth_for_orthographic_and_distance_for_perspective() {
    let eye = ortho().eye_homogeneous();
    // Off to the side but nearer the camera's plane: nearer for the parallel rays, though
    // farther from the camera's position.
    let (aside, behind) = (Vec3::new(30.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -5.0));
    assert!(farness(eye, aside) < farness(eye, behind));
    let persp = Vec3::new(0.0, 0.0, 10.0).extend(1.0);
    assert!(farness(persp, aside) > farness(persp, behind));
}
