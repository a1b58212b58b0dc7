//! What renderers on one context share, and what a resize rebuilds.
//!
//! - Programs and pipelines are compiled once per context (`GpuContext::program`): a second
//!   renderer of the same configuration compiles nothing and draws the same frame; one of
//!   another MSAA count adds pipelines (the render state is part of a pipeline's key, and a
//!   pipeline of the wrong sample count would be a validation error the harness fails on).
//! - The shadow settings are fitted to the output (`ShadowConfig::fitted`): a resize that
//!   changes them rebuilds the shadow pass, so the resized renderer draws what a renderer made
//!   at the new size draws.

use renderer::demo::{courtyard_look, light_space, pick_shadowed, procedural_lights};
use renderer::frame::{FrameCamera, RenderPath, Renderer, RendererConfig, default_camera};
use renderer::scene::{Scene, SceneLight};
use tests::frames::{largest_difference, render_one_frame};
use tests::gpu::gpu_test;

/// The courtyard with 64 lights, 6 of them shadowed as seen from `camera`, and a shadowed sun.
fn courtyard_lights(scene: &Scene, camera: &FrameCamera, height: u32) -> Vec<SceneLight> {
    let (region, (rmin, rmax)) = light_space(scene, true);
    let mut lights = procedural_lights(region, 64, 3, rmin, rmax);
    pick_shadowed(&mut lights, camera, height as f32, 6);
    lights.push(tests::frames::courtyard_sun());
    lights
}

fn renderer(
    gpu: &renderer::GpuContext,
    config: RendererConfig,
    scene: &Scene,
    lights: &[SceneLight],
) -> Renderer {
    let mut renderer = Renderer::new(gpu, config).expect("renderer");
    renderer.prepare_scene(scene).expect("the scene fits");
    renderer.set_lights(lights).expect("lights fit");
    renderer
}

#[test]
fn renderers_on_one_context_share_programs_and_pipelines_and_draw_the_same_frame() {
    let scene = renderer::scene::procedural::courtyard();
    let config = courtyard_look(RendererConfig {
        width: 96,
        height: 64,
        msaa: 4,
        path: RenderPath::Tiled,
        ..Default::default()
    });
    let camera = default_camera(&scene, 96.0 / 64.0);
    let lights = courtyard_lights(&scene, &camera, 64);
    gpu_test(|gpu| {
        let mut first = renderer(gpu, config, &scene, &lights);
        let want = render_one_frame(gpu, &mut first, &camera).rgba;
        let compiled = gpu.compiled();
        assert!(
            compiled.programs > 5 && compiled.pipelines > 5,
            "a Forward+ renderer with shadows compiles programs and pipelines: {compiled:?}"
        );

        let mut second = renderer(gpu, config, &scene, &lights);
        let got = render_one_frame(gpu, &mut second, &camera).rgba;
        assert_eq!(
            gpu.compiled(),
            compiled,
            "a second renderer of the same configuration compiled again"
        );
        assert_eq!(largest_difference(&want, &got), 0, "the frames differ");

        let single = RendererConfig { msaa: 1, ..config };
        let mut third = renderer(gpu, single, &scene, &lights);
        render_one_frame(gpu, &mut third, &camera);
        let grown = gpu.compiled();
        assert!(
            grown.pipelines > compiled.pipelines,
            "MSAA 1 needs pipelines of its own: {compiled:?} then {grown:?}"
        );
    });
}

#[test]
fn a_resize_that_changes_the_fitted_shadows_draws_as_a_renderer_made_at_the_new_size() {
    let scene = renderer::scene::procedural::courtyard();
    let small = courtyard_look(RendererConfig {
        width: 96,
        height: 64,
        path: RenderPath::Clustered,
        ..Default::default()
    });
    let large = RendererConfig {
        width: 480,
        height: 320,
        ..small
    };
    let (small_fit, large_fit) = (small.fitted_shadows(), large.fitted_shadows());
    assert_eq!(
        (small_fit.cascade_resolution, large_fit.cascade_resolution),
        (128, 512),
        "the sizes this test crosses"
    );
    let camera = default_camera(&scene, 480.0 / 320.0);
    let lights = courtyard_lights(&scene, &camera, 320);
    gpu_test(|gpu| {
        let mut resized = renderer(gpu, small, &scene, &lights);
        render_one_frame(gpu, &mut resized, &camera);
        resized
            .resize(480, 320)
            .expect("the device takes 480 x 320");
        let got = render_one_frame(gpu, &mut resized, &camera);
        let shadows = got.report.shadows.as_ref().expect("a shadow report");
        assert!(shadows.shadowed >= 7, "shadowed lights: {shadows:?}");

        let mut fresh = renderer(gpu, large, &scene, &lights);
        let want = render_one_frame(gpu, &mut fresh, &camera).rgba;
        assert_eq!(
            largest_difference(&want, &got.rgba),
            0,
            "the resized renderer's frame differs from a fresh one's"
        );
    });
}
