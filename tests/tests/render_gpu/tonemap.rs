//! The two tonemaps give the same frame: the compute kernel and its copy (a target with
//! `COPY_DST`) against the full-screen fragment pass (`compute_tonemap: false`, or a target
//! that takes no copies), on the courtyard through a deferred and a forward path at MSAA 4, and
//! on the particle-atlas view of the particle stage's smoke, whose source is scaled to the
//! target. Each frame's graph shows which tonemap ran. An `Rgba8Unorm` storage target is
//! written by the kernel itself, and so is `create_target`'s sRGB target, stored as its linear
//! twin: the same bytes as the copy, and the fragment pass draws the same frame into it through
//! its sRGB view.

use renderer::frame::{FrameView, RenderPath, Renderer, RendererConfig, create_target};
use renderer::readback;
use renderer::scene::procedural::{COURTYARD_LIGHT_REGION, courtyard};
use tests::frames::largest_difference;
use tests::gpu::gpu_test;
use tests::particle_stage;

/// A target of the configured format with `usage` (and `COPY_SRC` for the readback).
fn target_of(
    usage: wgpu::TextureUsages,
) -> impl FnOnce(&wgpu::Device, &RendererConfig) -> wgpu::Texture {
    move |device, config| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some("tonemap test target"),
            size: wgpu::Extent3d {
                width: config.width,
                height: config.height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: config.output_format,
            usage: usage | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        })
    }
}

/// One frame of the courtyard with `config` into the target `make_target` gives: its pixels
/// and its graph's passes.
fn tonemapped_frame(
    gpu: &renderer::GpuContext,
    config: RendererConfig,
    make_target: impl FnOnce(&wgpu::Device, &RendererConfig) -> wgpu::Texture,
) -> (Vec<u8>, Vec<String>) {
    // The particle-atlas view shows the particle stage's smoke, lit; the lit frame the courtyard.
    let (scene, lights, camera) = if config.view == FrameView::ParticleAtlas {
        let scene = particle_stage::stage();
        let lights = particle_stage::lights(&scene);
        (scene, lights, particle_stage::camera())
    } else {
        let scene = courtyard();
        let lights = renderer::demo::procedural_lights(COURTYARD_LIGHT_REGION, 64, 3, 0.8, 2.6);
        let camera = renderer::frame::framing_camera(scene.bounds, 16.0 / 9.0);
        (scene, lights, camera)
    };
    let mut renderer = Renderer::new(gpu, config).expect("renderer");
    renderer.prepare_scene(&scene).expect("scene");
    renderer.set_lights(&lights).expect("lights");
    renderer
        .set_particles(&particle_stage::particles(), 30)
        .expect("particles");
    let target = make_target(gpu.device(), &config);
    renderer.render(&camera, &target).expect("frame");
    renderer.finish();
    let passes = renderer.graph_passes().expect("the frame's graph");
    let rgba = readback::read_texture_rgba8(gpu.device(), gpu.queue(), &target).expect("readback");
    (rgba, passes)
}

#[test]
fn the_compute_tonemap_equals_the_fragment_tonemap() {
    use wgpu::TextureUsages as U;
    gpu_test(|gpu| {
        for (path, view) in [
            (RenderPath::TbdrPerSample, FrameView::Lit),
            (RenderPath::Clustered, FrameView::Lit),
            (RenderPath::Clustered, FrameView::ParticleAtlas),
        ] {
            let config = RendererConfig {
                width: 160,
                height: 90,
                msaa: 4,
                path,
                view,
                ..Default::default()
            };
            let what = format!("{path:?} {view:?}");
            let attachment_and_copies = U::RENDER_ATTACHMENT | U::COPY_DST;
            let copies = |passes: &[String]| passes.iter().any(|p| p == "tonemap copy");
            let (compute, compute_passes) =
                tonemapped_frame(gpu, config, target_of(attachment_and_copies));
            let fragment_config = RendererConfig {
                compute_tonemap: false,
                ..config
            };
            let (fragment, fragment_passes) =
                tonemapped_frame(gpu, fragment_config, target_of(attachment_and_copies));
            // A target that takes no copies gets the fragment pass, whatever the configuration.
            let (attachment_only, attachment_only_passes) =
                tonemapped_frame(gpu, config, target_of(U::RENDER_ATTACHMENT));
            // `create_target`'s target, stored as `Rgba8Unorm`: the kernel writes it, the
            // fragment pass draws into its sRGB view.
            let (stored_linear, stored_linear_passes) =
                tonemapped_frame(gpu, config, create_target);
            let (fragment_linear, _) = tonemapped_frame(gpu, fragment_config, |device, _| {
                create_target(device, &config)
            });
            let direct =
                |passes: &[String]| passes.iter().any(|p| p == "tonemap") && !copies(passes);
            assert!(
                direct(&stored_linear_passes),
                "{what}: {stored_linear_passes:?}"
            );
            assert!(
                stored_linear == compute,
                "{what}: the kernel into the target stored linear differs from its copy by {}",
                largest_difference(&stored_linear, &compute)
            );
            assert!(
                fragment_linear == fragment,
                "{what}: the fragment pass into the target stored linear, through its sRGB view, \
                 differs by {}",
                largest_difference(&fragment_linear, &fragment)
            );

            assert!(copies(&compute_passes), "{what}: {compute_passes:?}");
            assert!(!copies(&fragment_passes), "{what}: {fragment_passes:?}");
            assert!(
                !copies(&attachment_only_passes),
                "{what}: {attachment_only_passes:?}"
            );
            assert_eq!(
                fragment, attachment_only,
                "{what}: the fragment tonemap, chosen two ways"
            );
            let differing = compute
                .chunks(4)
                .zip(fragment.chunks(4))
                .filter(|(a, b)| a != b)
                .count();
            let worst = largest_difference(&compute, &fragment);
            eprintln!("{what}: {differing} pixels differ, by at most {worst}");
            assert!(
                worst <= 1,
                "{what}: the compute tonemap differs from the fragment pass by {worst}"
            );
            // The frame has content: not all one colour.
            assert!(
                compute.chunks(4).any(|p| p != &compute[..4]),
                "{what}: a blank frame"
            );
        }
    });
}

/// An `Rgba8Unorm` target that is a storage image is written by the kernel itself, without a
/// copy: a target with no other usage (no render attachment, no copies into it) shows the
/// same frame as the fragment pass draws into an attachment, linear as that format asks.
#[test]
fn the_compute_tonemap_writes_a_storage_target_itself() {
    use wgpu::TextureUsages as U;
    gpu_test(|gpu| {
        let config = RendererConfig {
            width: 160,
            height: 90,
            msaa: 4,
            path: RenderPath::Clustered,
            output_format: wgpu::TextureFormat::Rgba8Unorm,
            ..Default::default()
        };
        let (direct, direct_passes) = tonemapped_frame(gpu, config, target_of(U::STORAGE_BINDING));
        let fragment_config = RendererConfig {
            compute_tonemap: false,
            ..config
        };
        let (fragment, _) = tonemapped_frame(gpu, fragment_config, target_of(U::RENDER_ATTACHMENT));
        assert!(
            direct_passes.iter().any(|p| p == "tonemap")
                && !direct_passes.iter().any(|p| p == "tonemap copy"),
            "{direct_passes:?}"
        );
        let worst = largest_difference(&direct, &fragment);
        assert!(worst <= 1, "the storage target differs by {worst}");
        assert!(direct.chunks(4).any(|p| p != &direct[..4]), "a blank frame");
    });
}

/// Only an sRGB output takes a target stored as its linear twin: a linear output refuses an
/// sRGB target, and an sRGB output one of another linear format.
#[test]
fn a_target_of_another_format_is_refused() {
    use renderer::frame::{InputError, RenderError};
    use wgpu::TextureFormat as F;
    gpu_test(|gpu| {
        for (output_format, stored) in [
            (F::Rgba8Unorm, F::Rgba8UnormSrgb),
            (F::Rgba8UnormSrgb, F::Bgra8Unorm),
        ] {
            let config = RendererConfig {
                width: 32,
                height: 16,
                msaa: 1,
                path: RenderPath::Clustered,
                output_format,
                ..Default::default()
            };
            let scene = courtyard();
            let mut renderer = Renderer::new(gpu, config).expect("renderer");
            renderer.prepare_scene(&scene).expect("scene");
            let stored_config = RendererConfig {
                output_format: stored,
                ..config
            };
            let target =
                target_of(wgpu::TextureUsages::RENDER_ATTACHMENT)(gpu.device(), &stored_config);
            let camera = renderer::frame::framing_camera(scene.bounds, 2.0);
            let error = renderer.render(&camera, &target).map(|_| ()).unwrap_err();
            assert!(
                matches!(error, RenderError::Input(InputError::TargetMismatch { .. })),
                "{output_format:?} into {stored:?}: {error}"
            );
        }
    });
}
