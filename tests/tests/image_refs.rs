//! Image tests: frames of the committed scene compared with committed reference PNGs.
//!
//! Bound ([`tests::image_compare::compare_to_reference`]): every pixel within 3 per 8-bit
//! channel (RGBA) of the reference, except at most 0.5% of the pixels (72 of the 160×90), each of
//! which must still lie, channel by channel, within the range its reference 3×3 neighbourhood
//! spans widened by 3: what a rasterised edge moved by one pixel gives. The references are made
//! on lavapipe, and the same driver reproduces them within a step (measured: largest channel
//! difference 1 on all three); another LLVM or Mesa version may round transcendental functions
//! (pow, exp in the tonemapper and GGX) differently by a step or two, or move a rasterised edge
//! by a pixel. Anything else is a change to review.
//!
//! Re-approve after a deliberate change: `RENDERER_APPROVE_IMAGES=1 cargo test -p tests --test
//! image_refs`, then look at the new PNGs in `tests/images/` before committing them. A missing
//! reference fails the test (it never passes silently).

use std::path::{Path, PathBuf};

use renderer::demo::procedural_lights;
use renderer::frame::{FrameView, RenderPath, RendererConfig};
use renderer::scene::Scene;
use tests::frames::render_frame;
use tests::gpu::gpu_test;
use tests::image_compare::{ReferenceBound, compare_to_reference};

const APPROVE_ENV: &str = "RENDERER_APPROVE_IMAGES";
/// The bound of every reference image (see the module doc).
const BOUND: ReferenceBound = ReferenceBound {
    tolerance: 3,
    exceptions_per_mille: 5,
};

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
    let d = compare_to_reference(&got, want.as_raw(), config.width, BOUND);
    eprintln!(
        "{name}: largest channel difference {}, {} of {} pixels beyond {} (exceptions allowed {})",
        d.largest, d.beyond, d.pixels, BOUND.tolerance, d.allowed
    );
    assert!(
        d.passes(),
        "{name}: {} pixels differ by more than {} (allowed {}), {} of them outside their \
         reference neighbourhood's range (x, y, got, want): {:?}; re-approve with \
         {APPROVE_ENV}=1 if the change is deliberate",
        d.beyond,
        BOUND.tolerance,
        d.allowed,
        d.outside_neighbourhood.len(),
        &d.outside_neighbourhood[..d.outside_neighbourhood.len().min(10)]
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
        // The ambient the references were approved with (the default before the sky and
        // ground ambient).
        ambient: renderer::frame::Ambient::uniform(glam::Vec3::splat(0.03)),
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
