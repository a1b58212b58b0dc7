//! The web demo in a real browser: headless Chromium runs the `web` crate's wasm module (built
//! by `cargo xtask web --build-only`, which `cargo xtask test` runs first) on its WebGPU
//! (Dawn over SwiftShader's Vulkan driver), renders the courtyard with lights, shadows, decals
//! and particles on every path at MSAA 4 and three at MSAA 1, and reads each frame back
//! without blocking (`tests/web/browser_frame.html`). Each frame must equal the native frame
//! of the same settings and camera on lavapipe, and the culled paths must equal naive forward
//! in the browser too, and the page's per-pass GPU timings must cover the passes the native frame
//! times (WebGPU times whole compute and render passes only). The visibility path's kernels bind
//! more storage buffers than the browser's adapter offers: it must be refused by that limit's
//! name, not drawn wrong.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

use renderer::frame::RenderPath;
use serde_json::{Value, json};
use tests::browser::{ServedFile, files_under, run_page};
use tests::gpu::gpu_test;
use tests::image_compare::{pixel_differences, stats};
use web_demo::showcase::{Settings, Showcase};

use super::pass_timings::{COPY_ONLY, render_showcase_frame};

/// Loading the module, compiling every path's pipelines with Tint and rendering thirteen frames
/// on SwiftShader (measured: about 40 s on a 2-core machine).
const PAGE_TIMEOUT: Duration = Duration::from_secs(300);

/// What the page renders: small, so SwiftShader and lavapipe each draw a frame in about a
/// second, with every kind of content the demo has. The page opens on the first case (naive at
/// MSAA 4), so its first frame is read back after one renderer was built.
const SETTINGS: Settings = Settings {
    path: RenderPath::Naive,
    msaa: 4,
    width: 256,
    height: 144,
    lights: 64,
    shadowed: 4,
    decals: 24,
    particles: 1000,
    seed: 7,
};

/// The page's settings as its address's query.
fn query(s: &Settings) -> String {
    format!(
        "path={}&msaa={}&width={}&height={}&lights={}&shadowed={}&decals={}&particles={}&seed={}",
        s.path.name(),
        s.msaa,
        s.width,
        s.height,
        s.lights,
        s.shadowed,
        s.decals,
        s.particles,
        s.seed
    )
}

/// Every path at MSAA 4, then naive, tiled, clustered and visibility at MSAA 1.
fn cases() -> Vec<(RenderPath, u32)> {
    let mut cases: Vec<_> = RenderPath::ALL.iter().map(|&p| (p, 4)).collect();
    cases.extend(
        [
            RenderPath::Naive,
            RenderPath::Tiled,
            RenderPath::Clustered,
            RenderPath::Visibility,
        ]
        .map(|p| (p, 1)),
    );
    cases
}

/// What the browser's adapter (SwiftShader through Dawn) cannot do for a case, as the
/// renderer's refusal must name it: multisampled `R32Uint` (the visibility buffer; WebGPU
/// guarantees integer formats one sample), and the 19 storage buffers per stage the visibility
/// kernels bind (it offers 10).
fn refusal(path: RenderPath, msaa: u32) -> Option<&'static str> {
    match (path, msaa) {
        (RenderPath::Visibility, 1) => Some("max_storage_buffers_per_shader_stage"),
        (RenderPath::Visibility, _) => Some("MSAA 4 is not supported"),
        _ => None,
    }
}

/// Where `cargo xtask web` builds the demo: `target/web` (or under `CARGO_TARGET_DIR`).
fn web_build() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map_or_else(
            || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target"),
            PathBuf::from,
        )
        .join("web")
}

/// The newest modification time of the files under `dir`.
fn newest_under(dir: &Path) -> SystemTime {
    let mut newest = SystemTime::UNIX_EPOCH;
    for entry in std::fs::read_dir(dir)
        .expect("reading a source folder")
        .flatten()
    {
        let path = entry.path();
        let time = if path.is_dir() {
            newest_under(&path)
        } else {
            entry
                .metadata()
                .and_then(|m| m.modified())
                .expect("a file's time")
        };
        newest = newest.max(time);
    }
    newest
}

/// The page, the cases and the built module (under `pkg/`), which must be newer than the
/// sources it is built from (a stale module would test old code).
fn served_files() -> Vec<ServedFile> {
    let pkg = web_build().join("pkg");
    let module = pkg.join("web_demo_bg.wasm");
    let rebuild = "run `cargo xtask web --build-only --dev` (`cargo xtask test` does, before the \
                   tests)";
    let built = std::fs::metadata(&module)
        .and_then(|m| m.modified())
        .unwrap_or_else(|_| panic!("no web build at {}: {rebuild}", pkg.display()));
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    for crate_dir in ["web", "renderer", "shaders_gen", "codegen", "shader-bind"] {
        let sources = root.join(crate_dir).join("src");
        assert!(
            newest_under(&sources) <= built,
            "the web build at {} is older than {}: {rebuild}",
            pkg.display(),
            sources.display()
        );
    }
    let mut files: Vec<ServedFile> = files_under(&pkg)
        .unwrap_or_else(|e| panic!("{e}"))
        .into_iter()
        .map(|f| ServedFile {
            path: format!("pkg/{}", f.path),
            ..f
        })
        .collect();
    let listed: Vec<Value> = cases()
        .iter()
        .map(|(path, msaa)| json!({ "path": path.name(), "msaa": msaa }))
        .collect();
    files.push(ServedFile {
        path: "index.html".into(),
        content_type: "text/html; charset=utf-8",
        bytes: include_bytes!("../../web/browser_frame.html").to_vec(),
    });
    files.push(ServedFile {
        path: "scene.glb".into(),
        content_type: "model/gltf-binary",
        bytes: GLB.to_vec(),
    });
    files.push(ServedFile {
        path: "cases.json".into(),
        content_type: "application/json",
        bytes: serde_json::to_vec(&listed).expect("JSON"),
    });
    files
}

/// Writes a frame the browser rendered to `target/web/browser-frames/` for a reader to look
/// at (the closing note's pictures come from here).
fn save_browser_frame(label: &str, pixels: &[u8]) {
    let dir = web_build().join("browser-frames");
    std::fs::create_dir_all(&dir).expect("creating target/web/browser-frames");
    let name = label.replace(" at MSAA ", "-msaa").replace(' ', "-");
    image::save_buffer(
        dir.join(format!("{name}.png")),
        pixels,
        SETTINGS.width,
        SETTINGS.height,
        image::ColorType::Rgba8,
    )
    .expect("writing a browser frame");
}

/// `hex` (two digits a byte) as bytes.
fn unhex(hex: &str) -> Vec<u8> {
    (0..hex.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&hex[i..i + 2], 16).expect("hex"))
        .collect()
}

/// The glTF scene the page opens from its bytes after the courtyard.
const GLB: &[u8] = include_bytes!("../../scenes/AlphaBlendModeTest/AlphaBlendModeTest.glb");

/// The same frame rendered natively on lavapipe: its pixels, the names of its renderer's
/// passes, and the graph passes it timed (with timestamps between commands).
struct NativeFrame {
    pixels: Vec<u8>,
    passes: Vec<&'static str>,
    timed: BTreeSet<String>,
}

fn native_frame(
    gpu: &renderer::GpuContext,
    showcase: &Showcase,
    settings: &Settings,
) -> NativeFrame {
    let (mut renderer, target) = render_showcase_frame(gpu, showcase, settings);
    let pixels = renderer::readback::read_texture_rgba8(gpu.device(), gpu.queue(), &target)
        .expect("readback");
    let timings = renderer.finish().expect("lavapipe times the frame");
    NativeFrame {
        pixels,
        passes: renderer.pass_names(),
        timed: timings.into_iter().map(|t| t.pass).collect(),
    }
}

/// Checks the page's per-pass GPU timings of `frame`: the browser times whole compute and
/// render passes only, and still times every pass of its frame graph that the native frame
/// timed (the native graph has passes the browser's lacks, such as the draw compaction that
/// needs `MULTI_DRAW_INDIRECT_COUNT`), but for those that only copy; each with a time, the
/// frame above zero.
#[expect(
    clippy::print_stdout,
    reason = "the browser's timings are the test's report"
)]
fn timed_like_native(label: &str, frame: &Value, native: &NativeFrame) {
    let timings = frame["timings"].as_array().unwrap_or_else(|| {
        panic!(
            "{label}: no timings: the browser has no timestamp-query (Chromium on SwiftShader has)"
        )
    });
    let mut total = 0.0;
    let mut timed = BTreeSet::new();
    for t in timings {
        let (pass, ms) = (
            t[0].as_str().expect("a pass name"),
            t[1].as_f64().expect("ms"),
        );
        assert!(ms.is_finite() && ms >= 0.0, "{label}: {pass} took {ms} ms");
        total += ms;
        timed.insert(pass.to_owned());
    }
    let graph: BTreeSet<String> = frame["graph_passes"]
        .as_array()
        .expect("graph passes")
        .iter()
        .map(|p| p.as_str().expect("a pass name").to_owned())
        .collect();
    let expected: BTreeSet<String> = native
        .timed
        .intersection(&graph)
        .filter(|p| !COPY_ONLY.contains(&p.as_str()))
        .cloned()
        .collect();
    assert_eq!(timed, expected, "{label}: the browser timed other passes");
    assert!(total > 0.0, "{label}: a frame of no GPU time");
    println!(
        "{label}: {} passes timed in the browser, {total:.3} ms of GPU in them",
        timed.len()
    );
}

/// Checks the page's `frame` (its pixels and pass names, or its error) against the native
/// frame of `showcase` and `settings` on lavapipe, and returns the browser's pixels.
#[expect(
    clippy::print_stdout,
    reason = "the measured differences are the test's report"
)]
fn equal_to_native(
    gpu: &renderer::GpuContext,
    label: &str,
    frame: &Value,
    showcase: &Showcase,
    settings: &Settings,
) -> Vec<u8> {
    if let Some(error) = frame["error"].as_str() {
        panic!("{label}: the browser could not render it: {error}");
    }
    // The page ran what was asked: the same path, MSAA count and passes as the native renderer.
    assert_eq!(
        (frame["path"].as_str(), frame["msaa"].as_u64()),
        (Some(settings.path.name()), Some(u64::from(settings.msaa))),
        "{label}: the page ran other settings"
    );
    let pixels = unhex(frame["pixels"].as_str().expect("pixels"));
    save_browser_frame(label, &pixels);
    let native_frame = native_frame(gpu, showcase, settings);
    timed_like_native(label, frame, &native_frame);
    let (native, native_passes) = (native_frame.pixels, native_frame.passes);
    let passes: Vec<&str> = frame["passes"]
        .as_array()
        .expect("pass names")
        .iter()
        .map(|p| p.as_str().expect("a pass name"))
        .collect();
    assert_eq!(passes, native_passes, "{label}: the page ran other passes");
    let differences = pixel_differences(&pixels, &native, 3);
    let (mean, p99, max) = stats(&differences);
    let far = differences.iter().filter(|&&d| d > NATIVE_FAR).count();
    println!(
        "{label}: browser against lavapipe: mean {mean:.3}, p99 {p99}, max {max}, \
         {far} of {} pixels beyond {NATIVE_FAR}",
        differences.len()
    );
    assert!(
        mean <= NATIVE_MEAN
            && p99 <= NATIVE_P99
            && far * 1000 <= differences.len() * NATIVE_FAR_PER_MILLE,
        "{label}: the browser frame differs from lavapipe's: mean {mean:.3} (at most \
         {NATIVE_MEAN}), p99 {p99} (at most {NATIVE_P99}), {far} pixels beyond \
         {NATIVE_FAR} (at most {NATIVE_FAR_PER_MILLE} per 1,000)"
    );
    pixels
}

#[test]
#[expect(
    clippy::print_stdout,
    reason = "the measured differences and the time to first frame are this test's report"
)]
fn the_browser_frame_equals_the_native_frame_on_every_path_that_fits() {
    let files = served_files();
    let page = format!("index.html?{}", query(&SETTINGS));
    let posted = run_page(files, &page, PAGE_TIMEOUT).unwrap_or_else(|e| panic!("{e}"));
    let result: Value = serde_json::from_str(&posted).expect("the page posts JSON");
    if let Some(fatal) = result["fatal"].as_str() {
        panic!("the page failed: {fatal}");
    }
    let adapter = result["adapter"].as_str().unwrap_or("?");
    println!(
        "browser adapter: {adapter}\nfirst frame read back {:.0} ms after navigation",
        result["first_frame_ms"].as_f64().unwrap_or(f64::NAN)
    );
    let frames = result["frames"].as_array().expect("frames");
    assert_eq!(frames.len(), cases().len(), "one result per case");
    let mut browser = Vec::new();
    gpu_test(|gpu| {
        for ((path, msaa), frame) in cases().into_iter().zip(frames) {
            let label = format!("{} at MSAA {msaa}", path.name());
            if let Some(reason) = refusal(path, msaa) {
                let error = frame["error"].as_str().unwrap_or_else(|| {
                    panic!("{label}: drawn in a browser that cannot ({reason})")
                });
                assert!(
                    error.contains(reason),
                    "{label}: refused for another reason than `{reason}`: {error}"
                );
                println!("{label}: refused in the browser: {error}");
                continue;
            }
            let settings = Settings {
                path,
                msaa,
                ..SETTINGS
            };
            let showcase = Showcase::courtyard(&settings);
            let pixels = equal_to_native(gpu, &label, frame, &showcase, &settings);
            browser.push((path, msaa, pixels));
        }
        // The page opens it on Forward+ at MSAA 4.
        let settings = Settings {
            path: RenderPath::Tiled,
            msaa: 4,
            ..SETTINGS
        };
        let showcase = Showcase::from_gltf(GLB, &settings).expect("the committed scene loads");
        equal_to_native(
            gpu,
            "AlphaBlendModeTest from its bytes",
            &result["scene"],
            &showcase,
            &settings,
        );
    });
    for (path, msaa, pixels) in &browser {
        let naive = browser
            .iter()
            .find(|(p, m, _)| *p == RenderPath::Naive && m == msaa)
            .map(|(_, _, px)| px)
            .expect("naive at every MSAA count");
        let (mean, p99, max) = stats(&pixel_differences(pixels, naive, 3));
        println!(
            "{} at MSAA {msaa}: against naive in the browser: mean {mean:.3}, p99 {p99}, max {max}",
            path.name()
        );
        let holds = if path.is_deferred() {
            mean <= DEFERRED_MEAN && p99 <= DEFERRED_P99
        } else {
            max <= FORWARD_MAX
        };
        assert!(
            holds,
            "{} at MSAA {msaa}: differs from naive forward in the browser: mean {mean:.3}, \
             p99 {p99}, max {max}",
            path.name()
        );
    }
}

/// Browser against lavapipe, per pixel (largest RGB difference of 255). Two software
/// rasterisers with their own float rounding: about half the pixels differ by one level
/// (measured: mean 0.44–0.55, 99th percentile 1–2 on every case); a few sparks and highlights,
/// whose particles the two simulations move a little apart, by more (measured: at most 0.9
/// per 1,000 beyond 24, largest 209).
const NATIVE_MEAN: f64 = 1.5;
const NATIVE_P99: u8 = 3;
const NATIVE_FAR: u8 = 24;
const NATIVE_FAR_PER_MILLE: usize = 2;
/// Against naive forward within the browser, the bounds the native tests hold on lavapipe: the
/// forward paths' largest difference (`render_gpu`), the deferred paths' mean and 99th
/// percentile over the whole image (`tbdr_gpu`).
const FORWARD_MAX: u8 = 1;
const DEFERRED_MEAN: f64 = 0.3;
const DEFERRED_P99: u8 = 4;
