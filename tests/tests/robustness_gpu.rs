//! The renderer as an engine drives it for a long time, and misuses it: frame sizes the device
//! cannot take and targets of the wrong size are typed errors that change nothing; a lost device
//! is reported, and a new device renders the same lit frame again (both frames checked lit); 32
//! renderers of 25 frames each (every path, plain and scalarized, each MSAA count, sizes 1×1 and
//! odd ones) stay free of validation errors, keep the transient pool and the process's memory
//! bounded, and end on the frame a fresh renderer draws; and one renderer soaks 5,000 frames
//! (two scenes in turn, new lights every frame, resizes) with its wgpu objects and pool entries
//! exactly steady and the heap within 384 KiB after warm-up, ending on a fresh renderer's frame.

use renderer::demo::procedural_lights;
use renderer::frame::{
    ConfigError, DeviceError, FrameCamera, InputError, RenderError, RenderPath, Renderer,
    RendererConfig, create_target, framing_camera,
};
use renderer::readback;
use renderer::scene::{Scene, SceneLight};
use renderer::{GpuContext, GpuOptions};
use tests::frames::{committed_scene, largest_difference, render_one_frame};
use tests::gpu::gpu_test;
use tests::process_memory::{
    Checkpoint, Counting, heap_in_use, lit_pixels, live_objects, resident_bytes,
};

/// Counts the Rust side's heap for the soak's checkpoints.
#[global_allocator]
static ALLOCATOR: Counting = Counting;

fn lights(scene: &Scene, count: usize, seed: u64) -> Vec<SceneLight> {
    let size = (scene.bounds.max - scene.bounds.min).length();
    procedural_lights(scene.bounds, count, seed, size * 0.05, size * 0.3)
}

fn camera(scene: &Scene, config: &RendererConfig) -> FrameCamera {
    framing_camera(scene.bounds, config.width as f32 / config.height as f32)
}

/// The frame of `renderer` from `camera`, once its culled lists are complete.
fn draw(renderer: &mut Renderer, gpu: &GpuContext, camera: &FrameCamera) -> Vec<u8> {
    render_one_frame(gpu, renderer, camera).rgba
}

#[test]
fn sizes_and_targets_the_device_cannot_take_are_errors_that_change_nothing() {
    let scene = committed_scene();
    gpu_test(|gpu| {
        let max = gpu.device().limits().max_texture_dimension_2d;
        for (width, height) in [(0, 10), (10, 0), (max + 1, 16), (100_000, 100_000)] {
            let config = RendererConfig {
                width,
                height,
                ..Default::default()
            };
            let error = Renderer::new(gpu, config).map(|_| ()).unwrap_err();
            assert!(
                matches!(error, RenderError::Config(ConfigError::FrameSize { .. })),
                "{width}x{height}: {error}"
            );
            assert!(
                error.to_string().contains(&format!("1 to {max}")),
                "{error}"
            );
        }
        let config = RendererConfig {
            width: 64,
            height: 48,
            msaa: 1,
            ..Default::default()
        };
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        renderer
            .prepare_scene(&scene)
            .expect("the scene fits the device");
        let error = renderer.resize(max + 1, 8).unwrap_err();
        assert!(
            matches!(error, RenderError::Config(ConfigError::FrameSize { .. })),
            "{error}"
        );
        assert_eq!(
            (renderer.config().width, renderer.config().height),
            (64, 48)
        );
        let small = RendererConfig {
            width: 32,
            ..config
        };
        let wrong = create_target(gpu.device(), &small);
        let cam = camera(&scene, &config);
        let error = renderer.render(&cam, &wrong).map(|_| ()).unwrap_err();
        assert!(
            matches!(error, RenderError::Input(InputError::TargetMismatch { .. })),
            "{error}"
        );
        let srgb = RendererConfig {
            output_format: wgpu::TextureFormat::Bgra8UnormSrgb,
            ..config
        };
        let wrong = create_target(gpu.device(), &srgb);
        let error = renderer.render(&cam, &wrong).map(|_| ()).unwrap_err();
        assert!(error.to_string().contains("Bgra8UnormSrgb"), "{error}");
        // Nothing changed: the right target still renders.
        draw(&mut renderer, gpu, &cam);
    });
}

/// Both compared frames are checked lit ([`LOSS_LIT`]): a frame tonemapped black failed it.
#[test]
fn a_lost_device_is_an_error_and_a_new_device_draws_the_same_frame() {
    let scene = committed_scene();
    let lights = lights(&scene, 64, 5);
    let config = RendererConfig {
        width: 96,
        height: 64,
        msaa: 4,
        path: RenderPath::Tiled,
        // The ambient `LOSS_LIT` was measured at.
        ambient: renderer::frame::Ambient::uniform(glam::Vec3::splat(0.03)),
        ..Default::default()
    };
    let cam = camera(&scene, &config);
    let start = |gpu: &GpuContext| {
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        renderer
            .prepare_scene(&scene)
            .expect("the scene fits the device");
        renderer.set_lights(&lights).expect("lights fit");
        renderer
    };
    // The harness's device stays healthy; the test loses a device of its own.
    gpu_test(|_| {
        let first = GpuContext::new_blocking(&GpuOptions::validated()).expect("device");
        let mut renderer = start(&first);
        let before = draw(&mut renderer, &first, &cam);
        assert_lit(&before, "the frame before the loss", LOSS_LIT);
        let target = create_target(first.device(), &config);
        assert_eq!(first.lost(), None);
        first.device().destroy();
        // The lost callback runs when the device next does its upkeep.
        let _ = first.device().poll(wgpu::PollType::wait_indefinitely());
        let reason = first.lost().expect("the device reports its loss");
        assert!(reason.contains("Destroyed"), "{reason}");
        let error = renderer.render(&cam, &target).map(|_| ()).unwrap_err();
        assert!(
            matches!(error, RenderError::Device(DeviceError::DeviceLost(_))),
            "{error}"
        );
        assert!(error.is_device_lost(), "{error}");
        assert!(
            error.to_string().contains("create a new GpuContext"),
            "{error}"
        );
        drop((renderer, target, first));

        let second = GpuContext::new_blocking(&GpuOptions::validated()).expect("device");
        let mut renderer = start(&second);
        let after = draw(&mut renderer, &second, &cam);
        assert_lit(&after, "the new device's frame", LOSS_LIT);
        assert_eq!(largest_difference(&before, &after), 0);
    });
}

/// Frames of the many-renderer run (32 renderers of 25 frames: four rounds of every path,
/// plain and scalarized, each round at other MSAA counts), and how often it changes renderer
/// and size. What one
/// renderer accumulates over a long run is the one-renderer soak's to catch.
const RENDERERS_FRAMES: usize = 800;
const FRAMES_PER_RENDERER: usize = 25;
/// Growth of the heap in use allowed from the end of the second round of renderers (every path
/// plain and scalarized) to the end of the run. Each renderer, its pipelines and pool are
/// dropped before the next; what a software driver keeps (shader caches, allocator slabs) settles in those rounds. Mesa
/// 22.3's lavapipe failed this by gigabytes (it kept about 2.2 MB per draw call; `cargo xtask
/// test` installs a newer one).
const HEAP_GROWTH_LIMIT: u64 = 64 << 20;
/// Growth of resident memory allowed over the same frames: looser, since resident memory also
/// holds freed pages the allocator keeps (measured from +6 to +117 MiB between runs on Mesa
/// 25; Mesa 22.3's leak grew it by gigabytes).
const RESIDENT_GROWTH_LIMIT: u64 = 512 << 20;

#[test]
fn thirty_two_renderers_of_every_path_stay_bounded_and_end_on_a_fresh_renderers_frame() {
    let scene = committed_scene();
    let sizes = [(1, 1), (33, 17), (64, 48), (7, 91), (128, 72)];
    let light_counts = [0, 1, 17, 256];
    gpu_test(|gpu| {
        let msaa_counts = gpu.capabilities().msaa_counts();
        let subgroup = gpu.capabilities().subgroup.is_some();
        let before = live_objects(gpu);
        let mut settled = None;
        let mut last = None;
        let renderers = RENDERERS_FRAMES / FRAMES_PER_RENDERER;
        for r in 0..renderers {
            let path = RenderPath::ALL[r % RenderPath::ALL.len()];
            let (width, height) = sizes[r % sizes.len()];
            let config = RendererConfig {
                width,
                height,
                // Each round of paths shifts the MSAA counts, so every path meets several.
                msaa: msaa_counts[(r + r / RenderPath::ALL.len()) % msaa_counts.len()],
                path,
                tile: 16,
                // Every other round of paths is scalarized where the device can.
                scalarize: subgroup && (r / RenderPath::ALL.len()) % 2 == 1,
                ..Default::default()
            };
            let mut renderer = Renderer::new(gpu, config).expect("renderer");
            renderer
                .prepare_scene(&scene)
                .expect("the scene fits the device");
            let mut target = create_target(gpu.device(), renderer.config());
            let mut held = Vec::new();
            for f in 0..FRAMES_PER_RENDERER {
                if f % 10 == 0 {
                    let count = light_counts[(r + f / 10) % light_counts.len()];
                    renderer
                        .set_lights(&lights(&scene, count, (r * 100 + f) as u64))
                        .expect("lights fit");
                }
                if f == FRAMES_PER_RENDERER / 2 {
                    // Another size, odd ones included, on the same renderer.
                    let (w, h) = sizes[(r + 2) % sizes.len()];
                    renderer.resize(w, h).expect("size fits");
                    target = create_target(gpu.device(), renderer.config());
                }
                let cam = camera(&scene, renderer.config());
                let report = renderer.render(&cam, &target).expect("frame");
                held.push(report.pool.held);
                renderer
                    .wait_for_frames_in_flight(2)
                    .expect("frames finish");
            }
            renderer.finish();
            // The pool holds a steady set once a size has been seen for a few frames.
            let tail = &held[held.len() - 10..];
            assert!(
                tail.iter().all(|&h| h == tail[0]),
                "renderer {r} ({}): pool holds {tail:?} in its last frames",
                path.name()
            );
            // Dropping the previous renderer leaves this one alone.
            last = Some((renderer, target));
            // Two rounds of paths: every path plain and scalarized.
            if r + 1 == 2 * RenderPath::ALL.len() {
                gpu.wait_idle().expect("idle");
                settled = Some((heap_in_use(), resident_bytes()));
            }
        }
        gpu.wait_idle().expect("idle");
        let (heap, resident) = (heap_in_use(), resident_bytes());
        let (settled_heap, settled_resident) = settled.expect("two rounds of paths");
        eprintln!(
            "after two rounds of paths and after {RENDERERS_FRAMES} frames: heap in use {} and {} \
             MiB, resident {} and {} MiB",
            settled_heap >> 20,
            heap >> 20,
            settled_resident >> 20,
            resident >> 20
        );
        assert!(
            heap <= settled_heap + HEAP_GROWTH_LIMIT,
            "the heap in use grew from {} MiB to {} MiB",
            settled_heap >> 20,
            heap >> 20
        );
        assert!(
            resident <= settled_resident + RESIDENT_GROWTH_LIMIT,
            "resident memory grew from {} MiB to {} MiB",
            settled_resident >> 20,
            resident >> 20
        );

        // The last frame equals a fresh renderer's frame of the same settings.
        let (mut renderer, target) = last.expect("renderers ran");
        let config = *renderer.config();
        let lights = lights(&scene, 256, 7);
        renderer.set_lights(&lights).expect("lights fit");
        let cam = camera(&scene, &config);
        let soaked = draw(&mut renderer, gpu, &cam);
        let mut fresh = Renderer::new(gpu, config).expect("renderer");
        fresh
            .prepare_scene(&scene)
            .expect("the scene fits the device");
        fresh.set_lights(&lights).expect("lights fit");
        let clean = draw(&mut fresh, gpu, &cam);
        assert_eq!(largest_difference(&soaked, &clean), 0);

        // Every renderer gone, every wgpu object it made is gone too, once the
        // context lets go of the programs and pipelines it keeps for the next renderer.
        drop((renderer, target, fresh));
        gpu.release_compiled();
        gpu.wait_idle().expect("idle");
        assert_eq!(
            live_objects(gpu),
            before,
            "live wgpu objects after the renderers"
        );
    });
}

/// A pixel is lit at this Rec. 709 luma (0–255) or more.
const LIT_LUMA: f32 = 8.0;
/// The device-loss test's frames (the committed scene at 96 × 64, 64 lights, ambient 0.03) are
/// lit: measured 14.5 and 1,119 of 6,144.
const LOSS_LIT: (f32, usize) = (10.0, 800);

/// Panics unless `rgba` has a mean luma of `floor.0` or more and `floor.1` pixels or more at
/// [`LIT_LUMA`] or more.
fn assert_lit(rgba: &[u8], what: &str, floor: (f32, usize)) {
    let (mean, lit) = lit_pixels(rgba, LIT_LUMA);
    let pixels = rgba.len() / 4;
    eprintln!("{what}: mean luma {mean:.1}, {lit} of {pixels} pixels lit");
    assert!(
        mean >= floor.0 && lit >= floor.1,
        "{what} is not lit: mean luma {mean:.1} (floor {}), {lit} of {pixels} pixels at luma \
         {LIT_LUMA} or more (floor {})",
        floor.0,
        floor.1
    );
}

#[path = "robustness_gpu/soak.rs"]
mod soak;
