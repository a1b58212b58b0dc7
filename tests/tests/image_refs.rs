//! Image tests: frames of the committed scene compared with committed reference PNGs.
//!
//! Tolerance: 3 per 8-bit channel, and at most 0.5% of pixels beyond it. The references are made
//! on lavapipe; the same driver reproduces them exactly, and another LLVM or Mesa version may
//! round transcendental functions (pow, exp in the tonemapper and GGX) differently by a step or
//! two, or move a rasterized edge by a pixel. Anything larger is a change to review.
//!
//! Re-approve after a deliberate change: `RENDERER_APPROVE_IMAGES=1 cargo test -p tests --test
//! image_refs`, then look at the new PNGs in `tests/images/` before committing them. A missing
//! reference fails the test (it never passes silently).

use std::path::{Path, PathBuf};

use renderer::frame::setup::procedural_lights;
use renderer::frame::{FrameView, RenderPath, RendererConfig};
use renderer::scene::Scene;
use tests::frames::render_frame;
use tests::gpu::gpu_test;

const APPROVE_ENV: &str = "RENDERER_APPROVE_IMAGES";
const TOLERANCE: u8 = 3;

fn reference(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("images")
        .join(format!("{name}.png"))
}

fn render(config: RendererConfig) -> Vec<u8> {
    let scene_path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/AlphaBlendModeTest/AlphaBlendModeTest.glb");
    let scene = Scene::load(scene_path).unwrap_or_else(|e| panic!("{e}"));
    let size = (scene.bounds.max - scene.bounds.min).length();
    let lights = procedural_lights(scene.bounds, 96, 7, size * 0.04, size * 0.25);
    gpu_test(|gpu| render_frame(gpu, &scene, config, &lights).rgba)
}

fn check(name: &str, config: RendererConfig) {
    let got = render(config);
    let path = reference(name);
    if std::env::var(APPROVE_ENV).as_deref() == Ok("1") {
        std::fs::create_dir_all(path.parent().expect("images dir")).expect("create tests/images");
        image::save_buffer(
            &path,
            &got,
            config.width,
            config.height,
            image::ExtendedColorType::Rgba8,
        )
        .expect("write reference");
        return;
    }
    let want = image::open(&path)
        .unwrap_or_else(|e| panic!("reference {} is missing or unreadable ({e}); create it with {APPROVE_ENV}=1 and review it", path.display()))
        .to_rgba8();
    assert_eq!(
        (want.width(), want.height()),
        (config.width, config.height),
        "{name}: reference size"
    );
    let beyond = got
        .iter()
        .zip(want.as_raw())
        .filter(|(a, b)| a.abs_diff(**b) > TOLERANCE)
        .count();
    let allowed = got.len() / 200;
    assert!(
        beyond <= allowed,
        "{name}: {beyond} channel values differ by more than {TOLERANCE} (allowed {allowed}); re-approve with {APPROVE_ENV}=1 if the change is deliberate"
    );
}

fn small(path: RenderPath, msaa: u32, view: FrameView) -> RendererConfig {
    RendererConfig {
        width: 160,
        height: 90,
        msaa,
        path,
        view,
        heatmap_max: 64,
        ..Default::default()
    }
}

#[test]
fn forward_plus_frame_matches_its_reference() {
    check("tiled_msaa4", small(RenderPath::Tiled, 4, FrameView::Lit));
}

#[test]
fn clustered_frame_matches_its_reference() {
    check(
        "clustered_msaa1",
        small(RenderPath::Clustered, 1, FrameView::Lit),
    );
}

#[test]
fn heatmap_matches_its_reference() {
    check(
        "heatmap_tiled",
        small(RenderPath::Tiled, 1, FrameView::Heatmap),
    );
}
