//! The renderer as an engine drives it for a long time, and misuses it: frame sizes the device
//! cannot take and targets of the wrong size are typed errors that change nothing; a lost device
//! is reported, and a new device renders the same lit frame again (both frames checked lit); 32
//! renderers of 25 frames each (every path, plain and scalarized, each MSAA count, sizes 1×1 and
//! odd ones) stay free of validation errors, keep the transient pool and the process's memory
//! bounded, and end on the frame a fresh renderer draws; and one renderer soaks 5,000 frames
//! (two scenes in turn, new lights every frame, resizes) with its wgpu objects and pool entries
//! exactly steady and the heap within 384 KiB after warm-up, ending on a fresh renderer's frame.

use renderer::frame::setup::{create_target, framing_camera, procedural_lights};
use renderer::frame::{FrameCamera, RenderError, RenderPath, Renderer, RendererConfig};
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
        let max = gpu.device.limits().max_texture_dimension_2d;
        for (width, height) in [(0, 10), (10, 0), (max + 1, 16), (100_000, 100_000)] {
            let config = RendererConfig {
                width,
                height,
                ..Default::default()
            };
            let error = Renderer::new(gpu, config).map(|_| ()).unwrap_err();
            assert!(
                matches!(error, RenderError::FrameSize { .. }),
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
        assert!(matches!(error, RenderError::FrameSize { .. }), "{error}");
        assert_eq!(
            (renderer.config().width, renderer.config().height),
            (64, 48)
        );
        let small = RendererConfig {
            width: 32,
            ..config
        };
        let wrong = create_target(&gpu.device, &small);
        let cam = camera(&scene, &config);
        let error = renderer.render(&cam, &wrong).map(|_| ()).unwrap_err();
        assert!(
            matches!(error, RenderError::TargetMismatch { .. }),
            "{error}"
        );
        let srgb = RendererConfig {
            output_format: wgpu::TextureFormat::Bgra8UnormSrgb,
            ..config
        };
        let wrong = create_target(&gpu.device, &srgb);
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
        let target = create_target(&first.device, &config);
        assert_eq!(first.lost(), None);
        first.device.destroy();
        // The lost callback runs when the device next does its upkeep.
        let _ = first.device.poll(wgpu::PollType::wait_indefinitely());
        let reason = first.lost().expect("the device reports its loss");
        assert!(reason.contains("Destroyed"), "{reason}");
        let error = renderer.render(&cam, &target).map(|_| ()).unwrap_err();
        assert!(matches!(error, RenderError::DeviceLost(_)), "{error}");
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
            let mut target = create_target(&gpu.device, renderer.config());
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
                    target = create_target(&gpu.device, renderer.config());
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

        // Every renderer gone, every wgpu object it made is gone too.
        drop((renderer, target, fresh));
        gpu.wait_idle().expect("idle");
        assert_eq!(
            live_objects(gpu),
            before,
            "live wgpu objects after the renderers"
        );
    });
}

/// Frames of the one-renderer soak, and the period its schedule repeats with: each period shows
/// the committed scene (with decals) for its first half and the decal stage (another scene, with
/// other decals) for its second, at eight sizes ([`soak_size`]), and new lights every frame.
/// 10,000 frames took 72–113 s on lavapipe on a 2-core machine (beside other work); 5,000
/// (two warm-up periods and three checked) with the heap limit lowered to match keep catching
/// a leak of 128 bytes a frame.
const SOAK_FRAMES: usize = 5_000;
const PERIOD: usize = 1_000;
/// Frames of one size.
const SIZE_FRAMES: usize = PERIOD / 8;

/// The frame size of the soak's segment `segment` (of 8) in period `period`: 1 × 1 in the third,
/// 64 × 36 in the last (so that every period ends in the same state), and sizes that differ from
/// period to period in the others, so that a pool that kept what it no longer uses would grow.
fn soak_size(period: usize, segment: usize) -> (u32, u32) {
    match segment {
        2 => (1, 1),
        7 => (64, 36),
        k => (
            17 + ((period * 13 + k * 7) % 48) as u32,
            9 + ((period * 5 + k * 11) % 40) as u32,
        ),
    }
}

/// Periods run before the figures that later periods must keep to are taken.
const WARMUP_PERIODS: usize = 2;
/// Growth of glibc's heap in use allowed from the end of the warm-up to the end of any later
/// period (every period ends in the same state: scene, decals, size, light count). Lavapipe
/// allocates GPU memory on this heap, so leaked GPU memory counts. Measured (Mesa 25.0): at most
/// +37 KiB over the eight periods of a 10,000-frame soak (three runs); a leak of 128 bytes a
/// frame adds 384 KiB over the three checked periods. Under the
/// Khronos layer (Debian's 1.3.239) the same run grew 2.1–2.3 MiB every 1,000 frames while the Rust
/// side grew 13–28 KiB: the layer keeps about 2 KiB a frame, which is why the soak runs on a
/// device without it.
const SOAK_HEAP_GROWTH_LIMIT: i64 = 384 << 10;
/// Growth of the Rust side's heap (renderer, wgpu, this test; counted by [`Counting`]) allowed
/// over the same frames. Measured: at most +33 KiB (three runs).
const SOAK_RUST_HEAP_GROWTH_LIMIT: i64 = 256 << 10;
/// Growth of resident memory allowed over the same frames: resident memory also keeps freed
/// pages the allocator has not returned (measured: +4 to +10 MiB), so it only catches leaks of
/// megabytes a period.
const SOAK_RESIDENT_GROWTH_LIMIT: i64 = 32 << 20;
/// A pixel is lit at this Rec. 709 luma (0–255) or more.
const LIT_LUMA: f32 = 8.0;
/// The soak's checked frames (the decal stage at 64 × 36) are lit: mean luma and lit pixels at
/// least these (measured: 62–69 and 1,172 of 2,304; a black frame has 0 and 0).
const SOAK_LIT: (f32, usize) = (30.0, 900);
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

/// The lights of soak frame `frame` in `region`: a count from 0 to 40 and positions that change
/// every frame; the first two cast shadows.
fn soak_lights(region: renderer::scene::Aabb, frame: usize) -> Vec<SceneLight> {
    let count = (frame * 7 + frame / 13) % 41;
    let size = (region.max - region.min).length();
    let mut lights = procedural_lights(region, count, frame as u64, size * 0.1, size * 0.4);
    for light in lights.iter_mut().take(2) {
        light.casts_shadow = true;
    }
    lights
}

/// The soak's camera on scene `s` (0: the committed scene, framed; 1: the decal stage, from
/// above, so that its floor fills most of the frame).
fn soak_camera(scenes: &[Scene; 2], s: usize, config: &RendererConfig) -> FrameCamera {
    if s == 0 {
        return camera(&scenes[0], config);
    }
    let aspect = config.width as f32 / config.height as f32;
    let eye = glam::Vec3::new(0.0, 7.0, 4.5);
    FrameCamera::look_at(
        eye,
        glam::Vec3::ZERO,
        glam::Vec3::Y,
        1.0,
        aspect,
        (0.1, 50.0),
    )
}

/// Mutations this caught: a 256-byte buffer created and forgotten every frame (live buffers
/// 2,047 → 3,047 at frame 3,000), a transient pool that never evicts (pool entries 42 → 60,
/// textures 49 → 67), 256 bytes leaked on the Rust heap every frame (+271 KiB by frame 3,000),
/// and a frame tonemapped black (frame 1,000: mean luma 0, 0 lit pixels).
#[test]
fn one_renderer_soaks_five_thousand_changing_frames_with_bounded_memory_and_objects() {
    use renderer::decals::{DecalSet, placement::scatter, procedural};
    let scenes = [committed_scene(), tests::decal_stage::scene()];
    let decals = scenes.each_ref().map(|scene| DecalSet {
        materials: procedural::materials(),
        decals: scatter(scene, 12, 3, 11),
    });
    // The harness's validated device stays idle: the soak runs on a device of its own without
    // the Khronos layer (see `SOAK_HEAP_GROWTH_LIMIT`); wgpu's own validation stays on, and its
    // errors (and the harness's captured log errors) fail the test.
    gpu_test(|_| {
        let options = GpuOptions {
            flags: wgpu::InstanceFlags::empty(),
            ..GpuOptions::from_env()
        };
        let gpu = &GpuContext::new_blocking(&options).expect("device");
        let errors = std::sync::Arc::new(std::sync::Mutex::new(Vec::<String>::new()));
        let sink = std::sync::Arc::clone(&errors);
        gpu.device
            .on_uncaptured_error(std::sync::Arc::new(move |e| {
                sink.lock().expect("error list").push(e.to_string());
            }));
        let before = live_objects(gpu);
        let config = RendererConfig {
            width: 64,
            height: 36,
            msaa: 4,
            path: RenderPath::Clustered,
            ambient: renderer::frame::Ambient::uniform(glam::Vec3::splat(0.3)),
            shadows: renderer::shadow::ShadowConfig {
                atlas_size: 2048,
                max_resolution: 256,
                cascade_resolution: 256,
                ..Default::default()
            },
            ..Default::default()
        };
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        let mut target = create_target(&gpu.device, renderer.config());
        let mut settled = None;
        let started = std::time::Instant::now();
        for f in 0..SOAK_FRAMES {
            let phase = f % PERIOD;
            let s = phase * 2 / PERIOD;
            if phase.is_multiple_of(PERIOD / 2) {
                renderer.prepare_scene(&scenes[s]).expect("scene fits");
                renderer.set_decals(&decals[s]).expect("decals fit");
            }
            if phase.is_multiple_of(SIZE_FRAMES) {
                let (w, h) = soak_size(f / PERIOD, phase / SIZE_FRAMES);
                renderer.resize(w, h).expect("size fits");
                target = create_target(&gpu.device, renderer.config());
            }
            renderer
                .set_lights(&soak_lights(scenes[s].bounds, f))
                .expect("lights fit");
            let cam = soak_camera(&scenes, s, renderer.config());
            let report = renderer.render(&cam, &target).expect("frame");
            renderer
                .wait_for_frames_in_flight(2)
                .expect("frames finish");
            if !(f + 1).is_multiple_of(PERIOD) {
                continue;
            }
            renderer.finish();
            let rgba =
                readback::read_texture_rgba8(&gpu.device, &gpu.queue, &target).expect("readback");
            assert_lit(&rgba, &format!("soak frame {}", f + 1), SOAK_LIT);
            gpu.wait_idle().expect("idle");
            let now = Checkpoint::take(gpu, f + 1, report.pool.held);
            eprintln!("{:.1} s: {now:?}", started.elapsed().as_secs_f64());
            match settled {
                Some(settled) => now.assert_within(
                    &settled,
                    [
                        SOAK_HEAP_GROWTH_LIMIT,
                        SOAK_RUST_HEAP_GROWTH_LIMIT,
                        SOAK_RESIDENT_GROWTH_LIMIT,
                    ],
                ),
                None if f + 1 == WARMUP_PERIODS * PERIOD => settled = Some(now),
                None => {}
            }
        }

        // The soaked renderer draws what a fresh one draws.
        let lights = soak_lights(scenes[1].bounds, 3);
        renderer.set_lights(&lights).expect("lights fit");
        let cam = soak_camera(&scenes, 1, renderer.config());
        let soaked = draw(&mut renderer, gpu, &cam);
        let mut fresh = Renderer::new(gpu, *renderer.config()).expect("renderer");
        fresh.prepare_scene(&scenes[1]).expect("scene fits");
        fresh.set_decals(&decals[1]).expect("decals fit");
        fresh.set_lights(&lights).expect("lights fit");
        let clean = draw(&mut fresh, gpu, &cam);
        assert_lit(&clean, "the fresh renderer's frame", SOAK_LIT);
        assert_eq!(largest_difference(&soaked, &clean), 0);

        // The renderer gone, every wgpu object it made is gone too.
        drop((renderer, target, fresh));
        gpu.wait_idle().expect("idle");
        assert_eq!(
            live_objects(gpu),
            before,
            "live wgpu objects after the soak"
        );
        assert_eq!(*errors.lock().expect("error list"), Vec::<String>::new());
    });
}
