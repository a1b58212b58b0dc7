//! Several views in one frame (`Renderer::add_view`, `Renderer::render_views`): the particle
//! stage (smoke, shadowed lights) seen by the main view and by further views. The shadow atlas
//! is drawn once and the particles are stepped once per frame for every view: a view with the
//! main view's camera and another path draws what the main view draws, and the main view of a
//! renderer with views draws, frame after frame, exactly what a renderer without views draws.

use glam::Vec3;
use renderer::frame::InputError;
use renderer::frame::create_target;
use renderer::frame::{FrameCamera, RenderError, RenderPath, Renderer, RendererConfig, ViewTarget};
use renderer::readback::read_texture_rgba8;
use tests::frames::largest_difference;
use tests::gpu::gpu_test;
use tests::image_compare::{pixel_differences, stats};
use tests::particle_stage::{HEIGHT, WARMUP, WIDTH, camera, lights, particles, stage};

const FRAMES: usize = 4;

fn config(path: RenderPath) -> RendererConfig {
    RendererConfig {
        width: WIDTH,
        height: HEIGHT,
        msaa: 4,
        path,
        tile: 16,
        ..Default::default()
    }
}

fn renderer(gpu: &renderer::GpuContext) -> Renderer {
    let scene = stage();
    let mut r = Renderer::new(gpu, config(RendererConfig::default().path)).expect("renderer");
    r.prepare_scene(&scene).expect("scene");
    r.set_lights(&lights(&scene)).expect("lights");
    r.set_particles(&particles(), WARMUP).expect("particles");
    r
}

/// From behind the pillar, a smaller frame.
fn side_camera() -> FrameCamera {
    FrameCamera::look_at(
        Vec3::new(2.5, 2.0, 2.0),
        Vec3::new(0.0, 1.0, -0.5),
        Vec3::Y,
        60f32.to_radians(),
        4.0 / 3.0,
        (0.1, 30.0),
    )
}

#[test]
fn views_share_the_shadow_atlas_and_one_particle_step_per_frame() {
    gpu_test(|gpu| {
        let read =
            |t: &wgpu::Texture| read_texture_rgba8(gpu.device(), gpu.queue(), t).expect("readback");
        // A renderer with two further views: the main camera on the naive path, and a side
        // camera, smaller, without MSAA, on the clustered path.
        let mut with_views = renderer(gpu);
        let same = with_views
            .add_view(config(RenderPath::Naive))
            .expect("a view");
        let side_config = RendererConfig {
            width: 96,
            height: 72,
            msaa: 1,
            ..config(RenderPath::Clustered)
        };
        let side = with_views.add_view(side_config).expect("a view");
        let mut alone = renderer(gpu);
        // The side view alone: its own shadow plan and its own (equal) particle steps.
        let mut side_alone = renderer(gpu);
        side_alone
            .reconfigure(side_config)
            .expect("the side configuration");
        let main_target = create_target(gpu.device(), with_views.config());
        let same_target = create_target(gpu.device(), &config(RenderPath::Naive));
        let side_target = create_target(gpu.device(), &side_config);
        let alone_target = create_target(gpu.device(), alone.config());
        let side_target_alone = create_target(gpu.device(), &side_config);
        let cam = camera();
        let side_cam = side_camera();
        for frame in 0..FRAMES {
            let views = [
                ViewTarget {
                    view: same,
                    camera: &cam,
                    target: &same_target,
                },
                ViewTarget {
                    view: side,
                    camera: &side_cam,
                    target: &side_target,
                },
            ];
            let report = with_views
                .render_views(&cam, &main_target, &views)
                .expect("a frame of three views");
            alone.render(&cam, &alone_target).expect("a frame");
            side_alone
                .render(&side_cam, &side_target_alone)
                .expect("a frame");
            side_alone.finish();
            with_views.finish();
            alone.finish();
            assert_eq!(report.views.len(), 2);
            assert!(
                report.shadows.is_some(),
                "the main view draws the shadow atlas"
            );
            assert!(
                report.views.iter().all(|v| v.shadows.is_none()),
                "frame {frame}: a further view drew a shadow atlas of its own"
            );
            let main = read(&main_target);
            // Particles stepped once per frame: the main view is the lone renderer's frame.
            assert_eq!(
                largest_difference(&main, &read(&alone_target)),
                0,
                "frame {frame}: the main view differs from a renderer without views"
            );
            // The same camera on the naive path: the same shadows and smoke.
            let worst = largest_difference(&main, &read(&same_target));
            assert!(
                worst <= 2,
                "frame {frame}: the naive view differs by {worst}"
            );
            let side_image = read(&side_target);
            let lit = side_image
                .chunks(4)
                .filter(|p| p[0] > 16 || p[1] > 16 || p[2] > 16)
                .count();
            assert!(
                lit > 96 * 72 / 4,
                "frame {frame}: the side view is lit ({lit} pixels)"
            );
            let d = pixel_differences(&side_image, &read(&side_target_alone), 3);
            let (mean, p99, largest) = stats(&d);
            // Its own particle layout and lighting for its camera; its shadows are planned for
            // the main view (a light's shadow resolution follows the main view's size), which
            // moves a shadow edge texel by a step or two.
            assert!(
                mean <= 0.05 && largest <= 4,
                "frame {frame}: the side view differs from a lone renderer of its camera by \
                 mean {mean:.3}, largest {largest} (99th percentile {p99})"
            );
        }
    });
}

#[test]
fn bad_views_are_typed_errors_and_draw_nothing() {
    gpu_test(|gpu| {
        let mut r = renderer(gpu);
        let view = r.add_view(config(RenderPath::Naive)).expect("a view");
        let target = create_target(gpu.device(), r.config());
        let small = create_target(
            gpu.device(),
            &RendererConfig {
                width: 8,
                height: 8,
                ..config(RenderPath::Naive)
            },
        );
        let cam = camera();
        let twice = [
            ViewTarget {
                view,
                camera: &cam,
                target: &target,
            },
            ViewTarget {
                view,
                camera: &cam,
                target: &target,
            },
        ];
        assert!(
            matches!(r.render_views(&cam, &target, &twice), Err(RenderError::Input(InputError::ViewTwice(v))) if v == view)
        );
        let wrong_size = [ViewTarget {
            view,
            camera: &cam,
            target: &small,
        }];
        assert!(matches!(
            r.render_views(&cam, &target, &wrong_size),
            Err(RenderError::Input(InputError::TargetMismatch { .. }))
        ));
        r.remove_view(view).expect("removed");
        let gone = [ViewTarget {
            view,
            camera: &cam,
            target: &target,
        }];
        assert!(
            matches!(r.render_views(&cam, &target, &gone), Err(RenderError::Input(InputError::NoSuchView(v))) if v == view)
        );
        assert!(matches!(
            r.remove_view(view),
            Err(RenderError::Input(InputError::NoSuchView(_)))
        ));
        r.render_views(&cam, &target, &[])
            .expect("the main view alone");
    });
}
