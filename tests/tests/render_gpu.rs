//! The renderer end to end on the committed glTF scene and the built-in courtyard: culling never
//! changes the image. For seeded light sets, the tiled, 2.5D and clustered Forward+ images equal
//! the naive forward image (every light at every pixel) within a stated tolerance, at MSAA 1 and
//! 4 (the courtyard at 4). Lights without a range get an effective range that changes no pixel.

#[path = "render_gpu/browser.rs"]
mod browser;
#[path = "render_gpu/compute_raster.rs"]
mod compute_raster;
#[path = "render_gpu/default_raster.rs"]
mod default_raster;
#[path = "render_gpu/heatmap.rs"]
mod heatmap;
#[path = "render_gpu/material_programs.rs"]
mod material_programs;
#[path = "render_gpu/pass_timings.rs"]
mod pass_timings;
#[path = "render_gpu/sharing.rs"]
mod sharing;
#[path = "render_gpu/tonemap.rs"]
mod tonemap;
#[path = "render_gpu/views.rs"]
mod views;

use renderer::frame::ConfigError;
use std::path::Path;

use renderer::demo::procedural_lights;
use renderer::frame::framing_camera;
use renderer::frame::{RenderPath, Renderer, RendererConfig};
use renderer::frame_data::DEFAULT_LIGHT_CUTOFF;
use renderer::scene::{Scene, SceneLight};
use tests::frames::{
    committed_scene, largest_difference, render_frame, render_frame_from, render_one_frame,
};
use tests::gpu::gpu_test;

/// `count` seeded lights with ranges of 5–30% of the scene's size.
fn lights(scene: &Scene, count: usize, seed: u64, min: f32, max: f32) -> Vec<SceneLight> {
    let size = (scene.bounds.max - scene.bounds.min).length();
    procedural_lights(scene.bounds, count, seed, size * min, size * max)
}

/// One renderer of `path` at `msaa` on `scene`: its frame lit by each light set in turn (the
/// lights replaced between frames), read back.
fn render_sets(
    gpu: &renderer::GpuContext,
    scene: &Scene,
    path: RenderPath,
    msaa: u32,
    sets: &[Vec<SceneLight>],
) -> Vec<Vec<u8>> {
    let config = RendererConfig {
        width: 96,
        height: 64,
        msaa,
        path,
        tile: 16,
        ..Default::default()
    };
    let camera = framing_camera(scene.bounds, 96.0 / 64.0);
    let mut renderer = Renderer::new(gpu, config).expect("renderer");
    renderer.prepare_scene(scene).expect("the scene fits");
    sets.iter()
        .map(|lights| {
            renderer.set_lights(lights).expect("lights fit");
            // `render_one_frame` fails the test if a list entry was dropped.
            render_one_frame(gpu, &mut renderer, &camera).rgba
        })
        .collect()
}

#[test]
fn culling_never_changes_the_image() {
    let scene = committed_scene();
    let sets: Vec<Vec<SceneLight>> = [1u64, 2]
        .iter()
        .map(|&seed| lights(&scene, 64, seed, 0.05, 0.3))
        .collect();
    gpu_test(|gpu| {
        for msaa in [1, 4] {
            let naive = render_sets(gpu, &scene, RenderPath::Naive, msaa, &sets);
            for frame in &naive {
                let lit = frame
                    .chunks(4)
                    .filter(|p| p[0] > 8 || p[1] > 8 || p[2] > 8)
                    .count();
                assert!(
                    lit > frame.len() / 4 / 10,
                    "the scene must be visibly lit ({lit} pixels)"
                );
            }
            // The second set really replaced the first.
            assert!(largest_difference(&naive[0], &naive[1]) > 8);
            for path in [
                RenderPath::NaivePrez,
                RenderPath::Tiled,
                RenderPath::Depth25,
                RenderPath::Clustered,
            ] {
                let culled = render_sets(gpu, &scene, path, msaa, &sets);
                for (seed, (naive, culled)) in naive.iter().zip(&culled).enumerate() {
                    // Tolerance: one 8-bit step per channel. Culled paths sum the same lights
                    // in a different order (f32 addition is not associative) and lights
                    // dropped as borderline by a plane test contribute less than the window's
                    // last 1e-4.
                    let worst = largest_difference(naive, culled);
                    assert!(
                        worst <= 1,
                        "{path:?} at MSAA {msaa}, light set {seed}: differs from naive by {worst}"
                    );
                }
            }
        }
    });
}

/// Regression: with MSAA, edge fragments are shaded at the pixel centre, which may lie in a froxel
/// no visible sample occupies; skipping empty froxels there lost lights on DamagedHelmet.
#[test]
fn clustered_equals_naive_on_a_shared_scene_with_msaa() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/scenes/DamagedHelmet/glTF-Binary/DamagedHelmet.glb");
    assert!(
        path.is_file(),
        "shared scene {} is missing: this test needs ../shared/scenes",
        path.display()
    );
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let frame = |path: RenderPath| {
        let config = RendererConfig {
            width: 160,
            height: 90,
            msaa: 4,
            path,
            ..Default::default()
        };
        gpu_test(|gpu| {
            let frame = render_frame(gpu, &scene, config, &lights(&scene, 1024, 1, 0.03, 0.2));
            assert_eq!(frame.culling.map_or(0, |c| c.dropped), 0);
            frame.rgba
        })
    };
    let naive = frame(RenderPath::NaivePrez);
    let clustered = frame(RenderPath::Clustered);
    let worst = largest_difference(&naive, &clustered);
    assert!(worst <= 1, "clustered differs from naive by {worst}");
}

#[test]
fn the_built_in_courtyard_culled_equals_naive() {
    use renderer::scene::procedural::{COURTYARD_LIGHT_REGION, courtyard};
    let scene = courtyard();
    let lights = procedural_lights(COURTYARD_LIGHT_REGION, 256, 7, 0.8, 2.6);
    gpu_test(|gpu| {
        let frame = |path| {
            let config = RendererConfig {
                width: 128,
                height: 72,
                msaa: 4,
                path,
                tile: 16,
                ..Default::default()
            };
            let f = render_frame(gpu, &scene, config, &lights);
            assert_eq!(
                f.culling.map_or(0, |c| c.dropped),
                0,
                "{path:?} dropped lights"
            );
            f.rgba
        };
        let naive = frame(RenderPath::Naive);
        for path in [
            RenderPath::Tiled,
            RenderPath::Depth25,
            RenderPath::Clustered,
        ] {
            let culled = frame(path);
            let worst = largest_difference(&naive, &culled);
            assert!(worst <= 1, "{path:?}: differs from naive by {worst}");
        }
    });
}

/// The demo's own frame (courtyard, its camera and look, 1,024 lights, 640×360) in a
/// single-sample frame, where every list is narrowed by its tile's or froxel's view-space box:
/// every culled path equals the naive path with pre-Z. This frame found the BRDF's NaN (`pow` of
/// `1 − v·h` rounded below 0) that blackened a few naive pixels through lights that do not reach
/// them, and it checks the transparent lists on the glass.
#[test]
fn the_demo_frame_culled_equals_naive_without_msaa() {
    use renderer::demo::{courtyard_look, light_space};
    use renderer::frame::default_camera;
    use renderer::scene::procedural::courtyard;
    let scene = courtyard();
    let (region, (rmin, rmax)) = light_space(&scene, true);
    let mut lights = scene.lights.clone();
    lights.extend(procedural_lights(region, 1024, 1, rmin, rmax));
    let camera = default_camera(&scene, 640.0 / 360.0);
    gpu_test(|gpu| {
        let frame = |path| {
            let config = courtyard_look(RendererConfig {
                width: 640,
                height: 360,
                msaa: 1,
                path,
                tile: 16,
                ..Default::default()
            });
            let f = render_frame_from(gpu, &scene, config, &lights, &camera);
            let dropped = f.culling.map_or(0, |c| c.dropped);
            assert_eq!(dropped, 0, "{path:?} dropped lights");
            f.rgba
        };
        let naive = frame(RenderPath::NaivePrez);
        for path in [
            RenderPath::Tiled,
            RenderPath::Depth25,
            RenderPath::Clustered,
        ] {
            let culled = frame(path);
            let worst = largest_difference(&naive, &culled);
            assert!(worst <= 1, "{path:?}: differs from naive by {worst}");
        }
    });
}

/// LightsPunctualLamp's five point lights have no range (infinite, as glTF allows). The renderer
/// gives each the effective range where its illuminance falls to `light_cutoff`: the image stays
/// within one 8-bit step of the infinite lights' on naive forward, and the culled paths equal
/// naive forward with those ranges. A cutoff a million times larger (ranges inside the lamp)
/// visibly darkens it, so the comparison can fail.
#[test]
fn lights_without_a_range_get_an_effective_range_that_changes_no_pixel() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/scenes/LightsPunctualLamp/glTF/LightsPunctualLamp.gltf");
    assert!(
        path.is_file(),
        "shared scene {} is missing: this test needs ../shared/scenes",
        path.display()
    );
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(scene.lights.iter().all(|l| l.range.is_none()));
    gpu_test(|gpu| {
        let frame = |path: RenderPath, light_cutoff: f32| {
            let config = RendererConfig {
                width: 160,
                height: 120,
                msaa: 4,
                path,
                light_cutoff,
                ..Default::default()
            };
            render_frame(gpu, &scene, config, &scene.lights).rgba
        };
        let infinite = frame(RenderPath::NaivePrez, 0.0);
        let bounded = frame(RenderPath::NaivePrez, DEFAULT_LIGHT_CUTOFF);
        let worst = largest_difference(&infinite, &bounded);
        assert!(worst <= 1, "effective ranges change a pixel by {worst}");
        // Ranges of 4–44 cm, inside the lamp.
        let cut_short = frame(RenderPath::NaivePrez, DEFAULT_LIGHT_CUTOFF * 1.0e6);
        let short = largest_difference(&infinite, &cut_short);
        assert!(
            short > 8,
            "a 10^6x cutoff changes the image by only {short}"
        );
        for path in [RenderPath::Tiled, RenderPath::Clustered] {
            let culled = frame(path, DEFAULT_LIGHT_CUTOFF);
            let worst = largest_difference(&bounded, &culled);
            assert!(worst <= 1, "{} differs from naive by {worst}", path.name());
        }
        let bad = RendererConfig {
            light_cutoff: f32::NAN,
            ..Default::default()
        };
        let error = Renderer::new(gpu, bad).map(|_| ()).unwrap_err().to_string();
        assert!(error.contains("light cutoff NaN"), "{error}");
    });
}

/// No frame is wrong after a jump in list size: a clustered renderer that drew 16 small lights
/// is handed 2,048 lights larger than the scene (128×96 pixels, 8-pixel tiles, MSAA 4: over
/// four million list entries, more than the index list held before), and that very frame equals
/// naive forward: the index list is sized from a CPU bound before the frame, not grown after a
/// frame that dropped entries (`render_one_frame` fails any frame that dropped one).
#[test]
fn the_frame_after_a_jump_to_2048_huge_lights_equals_naive() {
    use renderer::scene::procedural::{COURTYARD_LIGHT_REGION, courtyard};
    let scene = courtyard();
    let few = procedural_lights(COURTYARD_LIGHT_REGION, 16, 3, 0.5, 1.0);
    let size = (COURTYARD_LIGHT_REGION.max - COURTYARD_LIGHT_REGION.min).length();
    let many = procedural_lights(COURTYARD_LIGHT_REGION, 2048, 4, size * 0.5, size * 2.0);
    let config = |path| RendererConfig {
        width: 128,
        height: 96,
        msaa: 4,
        path,
        tile: 8,
        ..Default::default()
    };
    gpu_test(|gpu| {
        let camera = framing_camera(scene.bounds, 128.0 / 96.0);
        let mut clustered = Renderer::new(gpu, config(RenderPath::Clustered)).expect("renderer");
        clustered.prepare_scene(&scene).expect("scene");
        clustered.set_lights(&few).expect("lights");
        let before = render_one_frame(gpu, &mut clustered, &camera);
        let small = before.culling.expect("counters").requested_entries;
        clustered.set_lights(&many).expect("lights");
        let jumped = render_one_frame(gpu, &mut clustered, &camera);
        let requested = jumped.culling.expect("counters").requested_entries;
        assert!(
            requested > 1 << 22 && requested > 100 * small.max(1),
            "the jump must outgrow any earlier list: {small} then {requested} entries"
        );
        let naive = render_frame_from(gpu, &scene, config(RenderPath::Naive), &many, &camera);
        let worst = largest_difference(&naive.rgba, &jumped.rgba);
        assert!(
            worst <= 1,
            "the frame after the jump differs from naive by {worst}"
        );
    });
}

/// Two coincident surfaces of different colours (two boxes with the same corners, red drawn
/// before green): naive forward and every path with a depth pre-pass keep the same one, the last
/// drawn, so each equals the scene with the green box alone, and culled equals naive exactly
/// there too. The red box alone differs visibly, so a path that kept red would fail.
#[test]
fn coincident_surfaces_look_the_same_on_every_path() {
    use glam::Vec3;
    use renderer::scene::procedural::SceneBuilder;
    let build = |boxes: &[Vec3]| {
        let mut b = SceneBuilder::new();
        let floor = b.material("floor", Vec3::splat(0.5), 0.8);
        b.cuboid(Vec3::new(-4.0, -0.1, -4.0), Vec3::new(4.0, 0.0, 4.0), floor);
        for (i, &color) in boxes.iter().enumerate() {
            let m = b.material(&format!("box {i}"), color, 0.6);
            b.cuboid(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 1.5, 1.0), m);
        }
        b.build()
    };
    let (red, green) = (Vec3::new(0.9, 0.02, 0.02), Vec3::new(0.02, 0.9, 0.02));
    let both = build(&[red, green]);
    let lights = lights(&both, 32, 5, 0.3, 0.8);
    let camera = framing_camera(both.bounds, 96.0 / 64.0);
    gpu_test(|gpu| {
        let frame = |scene: &Scene, path, msaa| {
            let config = RendererConfig {
                width: 96,
                height: 64,
                msaa,
                path,
                tile: 16,
                ..Default::default()
            };
            render_frame_from(gpu, scene, config, &lights, &camera).rgba
        };
        for msaa in [1, 4] {
            let green_only = frame(&build(&[green]), RenderPath::Naive, msaa);
            let red_only = frame(&build(&[red]), RenderPath::Naive, msaa);
            let visible = largest_difference(&green_only, &red_only);
            assert!(
                visible > 64,
                "MSAA {msaa}: the box's colour must show ({visible})"
            );
            for path in [
                RenderPath::Naive,
                RenderPath::NaivePrez,
                RenderPath::Tiled,
                RenderPath::Depth25,
                RenderPath::Clustered,
            ] {
                let worst = largest_difference(&green_only, &frame(&both, path, msaa));
                assert!(
                    worst <= 1,
                    "{path:?}, MSAA {msaa}: differs from the green box alone by {worst}"
                );
            }
        }
    });
}

#[test]
fn a_reconfigured_renderer_keeps_its_scene_and_renders_as_a_new_one() {
    let scene = committed_scene();
    // Rangeless lights: the cutoff and exposure give them their ranges.
    let lights: Vec<SceneLight> = lights(&scene, 48, 7, 0.05, 0.3)
        .into_iter()
        .map(|l| SceneLight { range: None, ..l })
        .collect();
    let camera = framing_camera(scene.bounds, 96.0 / 64.0);
    let first = RendererConfig {
        width: 96,
        height: 64,
        msaa: 1,
        path: RenderPath::Naive,
        tile: 16,
        ..Default::default()
    };
    // Another path, MSAA, tile and exposure, and a cutoff that shortens the lights' ranges
    // visibly.
    let second = RendererConfig {
        msaa: 4,
        path: RenderPath::Clustered,
        tile: 8,
        exposure: 1.7,
        light_cutoff: DEFAULT_LIGHT_CUTOFF * 2000.0,
        ..first
    };
    gpu_test(|gpu| {
        let mut renderer = Renderer::new(gpu, first).expect("renderer");
        renderer.prepare_scene(&scene).expect("the scene fits");
        renderer.set_lights(&lights).expect("lights fit");
        let before = render_one_frame(gpu, &mut renderer, &camera).rgba;
        renderer
            .reconfigure(second)
            .expect("the device runs the second configuration");
        // No `prepare_scene` or `set_lights` again.
        let after = render_one_frame(gpu, &mut renderer, &camera).rgba;

        let mut fresh = Renderer::new(gpu, second).expect("renderer");
        fresh.prepare_scene(&scene).expect("the scene fits");
        fresh.set_lights(&lights).expect("lights fit");
        let want = render_one_frame(gpu, &mut fresh, &camera).rgba;
        assert!(
            largest_difference(&before, &want) > 8,
            "the two configurations must render differently for this to show anything"
        );
        assert_eq!(
            largest_difference(&after, &want),
            0,
            "the reconfigured renderer differs from a new renderer of the same configuration"
        );

        // A configuration the device cannot run is refused, and nothing changes.
        let refused = renderer.reconfigure(RendererConfig { msaa: 3, ..second });
        assert!(
            matches!(
                refused,
                Err(renderer::frame::RenderError::Config(
                    ConfigError::SampleCount { asked: 3, .. }
                ))
            ),
            "{refused:?}"
        );
        assert_eq!(renderer.config().msaa, 4);
        let again = render_one_frame(gpu, &mut renderer, &camera).rgba;
        assert_eq!(largest_difference(&again, &want), 0);
    });
}
