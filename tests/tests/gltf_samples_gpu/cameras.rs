//! `Cameras`: a perspective and an orthographic camera looking at a unit square tilted 45°
//! away about X. Both cameras load; through the orthographic one the square's screen
//! rectangle is exactly what `xmag` / `ymag` give (a perspective camera would draw its far edge
//! shorter); a flat square lit by one directional light is one colour there (the view vector of
//! an orthographic camera is its axis, the same at every point); and with many point lights
//! every culled path equals naive forward with complete lists, so the tile frustums are built
//! with parallel sides.

use glam::{Quat, Vec3};
use renderer::demo::procedural_lights;
use renderer::frame::camera_of;
use renderer::frame::{FrameCamera, RenderPath, RendererConfig};
use renderer::scene::{CameraProjection, LightKind, Scene, SceneLight};
use tests::frames::{largest_difference, render_frame_from};
use tests::gpu::gpu_test;
use tests::image_compare::{pixel_differences, stats};

use super::sample;

const SIZE: u32 = 64;
const SKY: Vec3 = Vec3::new(0.0, 0.0, 0.5);

fn scene() -> Scene {
    sample("Cameras/Cameras.gltf")
}

fn config(path: RenderPath, msaa: u32) -> RendererConfig {
    RendererConfig {
        width: SIZE,
        height: SIZE,
        msaa,
        path,
        tile: 8,
        sky: SKY,
        ambient: renderer::frame::Ambient::OFF,
        ..Default::default()
    }
}

fn orthographic(scene: &Scene) -> FrameCamera {
    let camera = camera_of(scene, 1, 1.0).expect("camera 1");
    assert!(camera.orthographic, "camera 1 is the orthographic one");
    camera
}

#[test]
fn both_cameras_load_with_their_projections() {
    let scene = scene();
    assert_eq!(scene.cameras.len(), 2, "{:?}", scene.cameras);
    assert!(matches!(
        scene.cameras[0].projection,
        CameraProjection::Perspective { yfov, .. } if (yfov - 0.7).abs() < 1e-6
    ));
    assert_eq!(
        scene.cameras[1].projection,
        CameraProjection::Orthographic {
            xmag: 1.0,
            ymag: 1.0,
            znear: 0.01,
            zfar: 100.0
        }
    );
    assert!(!camera_of(&scene, 0, 1.0).expect("camera 0").orthographic);
    assert!(camera_of(&scene, 2, 1.0).is_none());
}

/// Whether pixel `(x, y)`'s centre sees the square, worked out by hand: the square's corners
/// `(0|1, 0|1, 0)` turned −45° about X (the file's node rotation) put its top edge at height
/// `cos 45°`; the camera at `(0.5, 0.5, 3)` looks down −Z and sees `±xmag` by `±ymag` (both 1)
/// around its axis, so view `x ∈ [−1, 1]` fills the 64 columns and `y ∈ [−1, 1]` the rows.
fn expected_square(x: u32, y: u32) -> bool {
    let vx = -1.0 + 2.0 * (x as f32 + 0.5) / SIZE as f32;
    let vy = 1.0 - 2.0 * (y as f32 + 0.5) / SIZE as f32;
    let (wx, wy) = (vx + 0.5, vy + 0.5);
    let top = Quat::from_xyzw(-0.383, 0.0, 0.0, 0.92375)
        .normalize()
        .mul_vec3(Vec3::Y)
        .y;
    (0.0..=1.0).contains(&wx) && (0.0..=top).contains(&wy)
}

/// The pixels that differ from the sky by more than a step.
fn covered(rgba: &[u8]) -> Vec<bool> {
    let sky = rgba[..4].to_vec();
    rgba.chunks(4)
        .map(|p| p.iter().zip(&sky).take(3).any(|(a, b)| a.abs_diff(*b) > 1))
        .collect()
}

fn sun() -> Vec<SceneLight> {
    vec![SceneLight {
        kind: LightKind::Directional,
        position: Vec3::ZERO,
        direction: Vec3::new(-0.3, -0.4, -1.0).normalize(),
        color: Vec3::ONE,
        intensity: 3.0,
        range: None,
        casts_shadow: false,
    }]
}

#[test]
fn the_orthographic_camera_shows_the_square_with_its_magnification() {
    let scene = scene();
    let camera = orthographic(&scene);
    gpu_test(|gpu| {
        let frame = render_frame_from(
            gpu,
            &scene,
            config(RenderPath::NaivePrez, 1),
            &sun(),
            &camera,
        );
        let seen = covered(&frame.rgba);
        let mut wrong = Vec::new();
        let mut count = 0;
        for y in 0..SIZE {
            for x in 0..SIZE {
                let expected = expected_square(x, y);
                count += usize::from(expected);
                if seen[(y * SIZE + x) as usize] != expected {
                    wrong.push((x, y, expected));
                }
            }
        }
        // Columns 16..=47 and rows 25..=47 by the arithmetic above.
        assert_eq!(count, 32 * 23);
        assert!(
            wrong.is_empty(),
            "{} pixels disagree with the orthographic square (x, y, expected): {:?}",
            wrong.len(),
            &wrong[..wrong.len().min(12)]
        );
    });
}

#[test]
fn a_flat_square_under_one_sun_is_one_colour_through_the_orthographic_camera() {
    let scene = scene();
    let camera = orthographic(&scene);
    gpu_test(|gpu| {
        for path in [
            RenderPath::NaivePrez,
            RenderPath::Tbdr,
            RenderPath::Deferred,
        ] {
            let rgba = render_frame_from(gpu, &scene, config(path, 1), &sun(), &camera).rgba;
            let inside: Vec<&[u8]> = (0..SIZE * SIZE)
                .filter(|&i| expected_square(i % SIZE, i / SIZE))
                .map(|i| &rgba[(i * 4) as usize..(i * 4 + 3) as usize])
                .collect();
            let first = inside[0];
            let spread = inside
                .iter()
                .map(|p| largest_difference(p, first))
                .max()
                .unwrap_or(0);
            assert!(
                first.iter().any(|&c| c > 20),
                "{path:?}: the square is lit ({first:?})"
            );
            assert!(
                spread <= 1,
                "{path:?}: the square's colour varies by {spread} across it (view vector)"
            );
        }
    });
}

#[test]
fn culled_paths_equal_naive_through_the_orthographic_camera() {
    let scene = scene();
    let camera = orthographic(&scene);
    let size = (scene.bounds.max - scene.bounds.min).length();
    let lights = procedural_lights(scene.bounds, 96, 7, size * 0.05, size * 0.3);
    gpu_test(|gpu| {
        for msaa in [1, 4] {
            let naive = render_frame_from(
                gpu,
                &scene,
                config(RenderPath::NaivePrez, msaa),
                &lights,
                &camera,
            )
            .rgba;
            let lit = covered(&naive).iter().filter(|&&c| c).count();
            assert!(lit > 500, "the square must be lit ({lit} pixels)");
            for path in [
                RenderPath::Tiled,
                RenderPath::Depth25,
                RenderPath::Clustered,
                RenderPath::Tbdr,
                RenderPath::TbdrPerSample,
                RenderPath::Deferred,
            ] {
                // `render_frame_from` fails the test if the frame dropped a list entry.
                let frame = render_frame_from(gpu, &scene, config(path, msaa), &lights, &camera);
                if path.is_culled() && !path.is_deferred() {
                    let c = frame.culling.expect("a culled path reports its lists");
                    assert!(c.requested_entries > 0, "{path:?}: lists are filled");
                }
                let d = pixel_differences(&naive, &frame.rgba, 3);
                let (mean, p99, worst) = stats(&d);
                if !path.is_deferred() {
                    // The tolerance of `render_gpu`'s `culling_never_changes_the_image`.
                    assert!(
                        worst <= 1,
                        "{path:?} at MSAA {msaa}: differs from naive by {worst}"
                    );
                } else if msaa == 1 {
                    // `tbdr_gpu`'s: the G-buffer's quantisation alone, at most 2 steps.
                    assert!(
                        worst <= 2,
                        "{path:?} at MSAA 1: differs from naive by {worst}"
                    );
                } else {
                    // `tbdr_gpu`'s whole-image tolerance with MSAA.
                    assert!(
                        mean <= 0.3 && p99 <= 4,
                        "{path:?} at MSAA {msaa}: mean {mean:.3}, 99th percentile {p99} \
                         (largest {worst})"
                    );
                }
            }
        }
    });
}
