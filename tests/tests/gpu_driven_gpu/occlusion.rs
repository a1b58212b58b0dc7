//! Two-phase occlusion culling: it leaves out draws the frustum keeps (a wall in front of the
//! street camera hides what is behind it), and never a visible one: every frame equals the
//! same frame with culling off, including the first one (no history), the frame the wall
//! moves away and what it hid appears (drawn by the second phase), and a half turn of the
//! camera in one frame.

use glam::{Mat4, Quat, Vec3};
use renderer::frame::{FrameCamera, RenderPath, Renderer, RendererConfig, VisibilityRaster};
use renderer::scene::Scene;
use tests::frames::{largest_difference, render_one_frame};
use tests::gpu::gpu_test;

use super::{city, config, street_camera, street_lights};

/// What one frame drew and how many slots culling kept.
struct Frame {
    rgba: Vec<u8>,
    kept: Option<u32>,
}

/// A step of the script: move the wall (instance handle 0 of the added ones) or the camera.
#[derive(Clone, Copy)]
enum Step {
    Hold,
    WallAway,
    Turn,
}

/// Renders the script with `config`: a wall added right in front of the camera, then `steps`.
fn script(
    gpu: &renderer::GpuContext,
    scene: &Scene,
    lights: &[renderer::scene::SceneLight],
    config: RendererConfig,
    camera: &FrameCamera,
    steps: &[Step],
) -> Vec<Frame> {
    let mut renderer = Renderer::new(gpu, config).expect("renderer");
    renderer.prepare_scene(scene).expect("the city fits");
    renderer.set_lights(lights).expect("lights fit");
    let tower = scene
        .meshes
        .iter()
        .position(|m| m.name == "tower")
        .expect("a tower mesh");
    let forward = (camera.view.inverse().transform_vector3(Vec3::NEG_Z)).normalize();
    let wall_at = Mat4::from_scale_rotation_translation(
        Vec3::new(40.0, 30.0, 40.0),
        Quat::IDENTITY,
        camera.eye + forward * 30.0 - Vec3::Y * 5.0,
    );
    let wall = renderer.add_instance(tower, wall_at).expect("a mesh");
    let mut camera = *camera;
    steps
        .iter()
        .map(|step| {
            match step {
                Step::Hold => {}
                Step::WallAway => renderer
                    .set_instance_transform(wall, Mat4::from_translation(Vec3::Y * -1.0e4))
                    .expect("the wall"),
                Step::Turn => {
                    let turn = Mat4::from_rotation_y(std::f32::consts::PI);
                    let at = Mat4::from_translation(camera.eye);
                    camera.view = camera.view * at * turn * at.inverse();
                }
            }
            let rgba = render_one_frame(gpu, &mut renderer, &camera).rgba;
            let kept = renderer.scene_draws().and_then(|d| d.visible);
            Frame { rgba, kept }
        })
        .collect()
}

#[test]
fn occlusion_culling_hides_what_a_wall_hides_and_never_a_visible_draw() {
    let city = city(2_000);
    let lights = street_lights(&city);
    let camera = street_camera(&city.scene);
    let steps = [
        Step::Hold,
        Step::Hold,
        Step::Hold,
        Step::Hold,
        Step::WallAway,
        Step::Turn,
        Step::Hold,
    ];
    gpu_test(|gpu| {
        // Under the compute rasteriser the depth pyramid is seeded from its buffer of samples,
        // which its first half wrote.
        let (hardware, compute) = (VisibilityRaster::Hardware, VisibilityRaster::Compute);
        for (path, msaa, raster) in [
            (RenderPath::Tiled, 4, hardware),
            (RenderPath::Tbdr, 1, hardware),
            (RenderPath::Visibility, 4, hardware),
            (RenderPath::Visibility, 4, compute),
        ] {
            let run = |cull: bool, occlusion: bool| {
                let c = RendererConfig {
                    occlusion_cull: occlusion,
                    visibility_raster: raster,
                    ..config(path, msaa, cull)
                };
                script(gpu, &city.scene, &lights, c, &camera, &steps)
            };
            let occluded = run(true, true);
            let frustum = run(true, false);
            let all = run(false, false);

            for (i, (o, a)) in occluded.iter().zip(&all).enumerate() {
                let worst = largest_difference(&o.rgba, &a.rgba);
                assert_eq!(
                    worst, 0,
                    "{path:?} ({raster:?}), frame {i}: occlusion culling changed a pixel by {worst}"
                );
            }
            // Frame 0 has no history: its first phase draws nothing, its second everything in
            // the frustum (the compute rasteriser too, which rasterises the slots each phase
            // keeps). Frame 1's first phase draws all that (so it keeps as many), and its test
            // finds what the wall hides; from frame 2 on, occlusion keeps far fewer draws than
            // the frustum.
            let kept = |frames: &[Frame], i: usize| frames[i].kept.expect("a culled count");
            assert_eq!(
                kept(&occluded, 0),
                kept(&frustum, 0),
                "{path:?} ({raster:?}), frame 0"
            );
            for i in [2, 3] {
                assert!(
                    kept(&occluded, i) * 3 < kept(&frustum, i),
                    "{path:?} ({raster:?}), frame {i}: occlusion kept {} of the frustum's {}",
                    kept(&occluded, i),
                    kept(&frustum, i)
                );
            }
            assert!(
                kept(&occluded, 4) > 2 * kept(&occluded, 3),
                "{path:?} ({raster:?}): the wall gone, what it hid is drawn ({} then {})",
                kept(&occluded, 3),
                kept(&occluded, 4)
            );
            assert!(
                largest_difference(&all[3].rgba, &all[4].rgba) > 32
                    && largest_difference(&all[4].rgba, &all[5].rgba) > 32,
                "{path:?}: the wall's move and the turn must show"
            );
        }
    });
}

/// The CPU reference of the pyramid: level 0 half the frame rounded up to powers of two, each
/// texel the largest of its 2×2 pixels of `depth` (indices clamped to the frame); each level
/// above half the one below, each texel the largest of its 2×2 texels below (clamped), down to
/// 1×1.
fn reference_pyramid(width: u32, height: u32, depth: &[f32]) -> Vec<(u32, u32, Vec<f32>)> {
    let mut levels: Vec<(u32, u32, Vec<f32>)> = Vec::new();
    let (mut w, mut h, mut below) = (width, height, depth.to_vec());
    loop {
        let (nw, nh) = if levels.is_empty() {
            (
                w.div_ceil(2).next_power_of_two(),
                h.div_ceil(2).next_power_of_two(),
            )
        } else {
            ((w / 2).max(1), (h / 2).max(1))
        };
        let mut level = Vec::with_capacity((nw * nh) as usize);
        for y in 0..nh {
            for x in 0..nw {
                let mut farthest = f32::MIN;
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let (sx, sy) = ((2 * x + dx).min(w - 1), (2 * y + dy).min(h - 1));
                    farthest = farthest.max(below[(sy * w + sx) as usize]);
                }
                level.push(farthest);
            }
        }
        levels.push((nw, nh, level.clone()));
        if nw == 1 && nh == 1 {
            return levels;
        }
        (w, h, below) = (nw, nh, level);
    }
}

#[test]
fn the_depth_pyramid_equals_a_cpu_reduction_of_the_depth() {
    let city = city(300);
    let lights = street_lights(&city);
    let camera = street_camera(&city.scene);
    gpu_test(|gpu| {
        let mut renderer =
            Renderer::new(gpu, config(RenderPath::Tiled, 1, true)).expect("renderer");
        renderer.prepare_scene(&city.scene).expect("the city fits");
        renderer.set_lights(&lights).expect("lights fit");
        // Frame 0 has no history and finds everything in the frustum visible; frame 1's first
        // phase draws all of it, so the pyramid (built from that phase's depth) and the
        // frame's final depth come from the same draws.
        render_one_frame(gpu, &mut renderer, &camera);
        renderer.capture_next_frame(1).expect("a depth pre-pass");
        render_one_frame(gpu, &mut renderer, &camera);
        let capture = renderer
            .take_capture()
            .expect("read back")
            .expect("a capture");
        let (w, h) = (capture.grid.x, capture.grid.y);
        assert_eq!((w, h), super::SIZE);
        let expected = reference_pyramid(w, h, &capture.probes);
        let pass = renderer
            .pass::<renderer::passes::scene_cull::occlusion::OcclusionCullPass>()
            .expect("occlusion culling runs");
        let levels = pass.read_pyramid(gpu).expect("read back");
        assert_eq!(levels.len(), expected.len(), "levels down to 1×1");
        for (k, (got, (ew, eh, texels))) in levels.iter().zip(&expected).enumerate() {
            assert_eq!((got.width, got.height), (*ew, *eh), "level {k}");
            let wrong = got
                .texels
                .iter()
                .zip(texels)
                .filter(|(a, b)| a != b)
                .count();
            assert_eq!(
                wrong, 0,
                "level {k}: {wrong} texels differ from the reference"
            );
        }
        let near = expected[0].2.iter().filter(|&&d| d < 1.0).count();
        assert!(near > expected[0].2.len() / 2, "the street fills the frame");
    });
}
