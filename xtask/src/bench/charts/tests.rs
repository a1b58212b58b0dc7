//! Tests of the benchmark charts: every chart of a grid of records, single records, values a log
//! axis cannot show, file names, tick choice, and the embedded font.

use super::axes::log_ticks;
use super::*;

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("xtask-charts-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// A plausible cell: times grow with the light count, culled paths more slowly.
fn record(path: &str, tile: u32, scalarize: bool, msaa: u32, lights: u32) -> CellRecord {
    let culled = path != "naive" && path != "naive-prez";
    let n = f64::from(lights);
    let spread =
        1.0 + (path.len() as f64 + f64::from(tile) + f64::from(u8::from(scalarize))) / 20.0;
    let forward = spread
        * if culled {
            0.3 + n.sqrt() * 0.01
        } else {
            0.2 + n * 0.002
        };
    let cull = culled.then(|| spread * (0.05 + n * 1e-4 * f64::from(tile.max(8)) / 16.0));
    CellRecord {
        scene: "Sponza Atrium".into(),
        width: 1920,
        height: 1080,
        msaa,
        path: path.into(),
        tile,
        scalarize,
        brute_force: false,
        lights,
        frames: 64,
        prez_median_ms: (path != "naive").then_some(0.1),
        prez_p90_ms: (path != "naive").then_some(0.12),
        cull_median_ms: cull,
        cull_depth_median_ms: None,
        cull_coarse_median_ms: None,
        cull_fine_median_ms: None,
        cull_p90_ms: cull.map(|c| c * 1.1),
        forward_median_ms: Some(forward),
        forward_p90_ms: Some(forward * 1.1),
        tonemap_median_ms: Some(0.02),
        tonemap_p90_ms: Some(0.03),
        gpu_total_median_ms: 0.15 + forward + cull.unwrap_or(0.0),
        cpu_graph_median_ms: 0.3,
        cpu_upload_median_ms: 0.1,
        grid_bytes: if culled { 1 << 16 } else { 0 },
        index_bytes_used: 0,
        index_bytes_allocated: 0,
        cull_efficiency: culled.then(|| 1.2 + f64::from(tile) / 16.0 + n.log2() * 0.05),
        lights_reaching_mean: Some(n.sqrt()),
        cull_floor_us: None,
        dropped: 0,
        note: String::new(),
        ..Default::default()
    }
}

/// Every path of the matrix at four light counts and two MSAA counts, with gaps.
fn grid() -> Vec<CellRecord> {
    let paths = [
        ("naive", 0, false),
        ("naive-prez", 0, false),
        ("tiled", 8, false),
        ("tiled", 16, false),
        ("tiled", 16, true),
        ("tiled", 32, false),
        ("2.5d", 16, false),
        ("2.5d", 32, false),
        ("clustered", 0, false),
        ("clustered", 0, true),
    ];
    let mut records = Vec::new();
    for msaa in [1, 4] {
        for (path, tile, scalarize) in paths {
            for lights in [64, 256, 1024, 4096] {
                let mut r = record(path, tile, scalarize, msaa, lights);
                if path == "tiled" && lights == 256 {
                    r.forward_median_ms = None;
                }
                if path == "clustered" && lights == 1024 {
                    r.cull_efficiency = None;
                    r.cull_median_ms = None;
                }
                records.push(r);
            }
        }
    }
    records
}

fn assert_png(path: &Path, size: (u32, u32)) {
    let image = image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let image = image.to_rgb8();
    assert_eq!(image.dimensions(), size, "{}", path.display());
    let first = image.get_pixel(0, 0);
    assert!(
        image.pixels().any(|p| p != first),
        "{} is one flat colour",
        path.display()
    );
    let RGBColor(r, g, b) = COLORS[0];
    assert!(
        image.pixels().any(|p| p.0 == [r, g, b]),
        "{} draws no line in the first colour",
        path.display()
    );
}

const GPU_SIZE: (u32, u32) = (3 * PANEL_WIDTH + LEGEND_WIDTH, CHART_HEIGHT);
const EFFICIENCY_SIZE: (u32, u32) = (PANEL_WIDTH + PANEL_WIDTH / 2 + LEGEND_WIDTH, CHART_HEIGHT);

#[test]
fn writes_every_chart_of_a_grid() {
    let dir = temp_dir("grid");
    let written = write_charts(&grid(), &dir).unwrap();
    let names: Vec<String> = written
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        [
            "gpu_Sponza_Atrium_1920x1080_msaa1.png",
            "cull_efficiency_Sponza_Atrium_1920x1080_msaa1.png",
            "gpu_Sponza_Atrium_1920x1080_msaa4.png",
            "cull_efficiency_Sponza_Atrium_1920x1080_msaa4.png",
        ]
    );
    for path in &written {
        assert_eq!(path.parent(), Some(dir.as_path()));
        let gpu = path
            .file_name()
            .unwrap()
            .to_string_lossy()
            .starts_with("gpu_");
        assert_png(path, if gpu { GPU_SIZE } else { EFFICIENCY_SIZE });
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn one_record_makes_charts_without_panicking() {
    let dir = temp_dir("one");
    let written = write_charts(&[record("tiled", 16, false, 1, 100)], &dir).unwrap();
    assert_eq!(written.len(), 2);
    assert_png(&written[0], GPU_SIZE);
    assert_png(&written[1], EFFICIENCY_SIZE);

    // A path without culling: the culling panel is empty and there is no efficiency chart.
    let written = write_charts(&[record("naive", 0, false, 8, 1)], &dir).unwrap();
    assert_eq!(written, [dir.join("gpu_Sponza_Atrium_1920x1080_msaa8.png")]);
    assert_png(&written[0], GPU_SIZE);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn unplottable_values_skip_charts_without_panicking() {
    let dir = temp_dir("unplottable");
    let mut zero = record("clustered", 0, false, 2, 0);
    zero.gpu_total_median_ms = 0.0;
    zero.forward_median_ms = Some(f64::NAN);
    zero.cull_median_ms = None;
    zero.cull_efficiency = Some(f64::INFINITY);
    assert_eq!(write_charts(&[zero], &dir).unwrap(), Vec::<PathBuf>::new());
    // Only tile 8: not on the GPU chart, but on the efficiency chart.
    let written = write_charts(&[record("tiled", 8, false, 1, 64)], &dir).unwrap();
    assert_eq!(
        written,
        [dir.join("cull_efficiency_Sponza_Atrium_1920x1080_msaa1.png")]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn empty_input_writes_nothing() {
    let dir = temp_dir("empty");
    assert!(write_charts(&[], &dir).unwrap().is_empty());
    assert!(!dir.exists());
}

#[test]
fn scene_names_are_sanitized() {
    assert_eq!(sanitize("Sponza Atrium"), "Sponza_Atrium");
    assert_eq!(sanitize("../a/b.c-d_e"), "___a_b_c-d_e");
    assert_eq!(sanitize(""), "scene");
}

#[test]
fn log_ticks_span_the_values() {
    let (range, ticks) = log_ticks(0.3, 4.0);
    assert_eq!(range, 0.2..5.0);
    assert_eq!(ticks.len(), 5); // 0.2 0.5 1 2 5
    let (range, ticks) = log_ticks(1.0, 1.0);
    assert!(range.start < 1.0 && range.end > 1.0);
    assert_eq!(ticks.len(), 3); // 0.5 1 2
    let (_, ticks) = log_ticks(0.25, 0.4);
    assert_eq!(ticks.len(), 4); // 0.2 0.3 0.4 0.5
    let (_, ticks) = log_ticks(1e-3, 1e3);
    assert_eq!(ticks.len(), 7); // powers of ten only: 0.001 to 1000
    assert_eq!(format_value(0.05), "0.05");
    assert_eq!(format_value(20.0), "20");
    assert_eq!(format_value(1.5), "1.5");
    assert_eq!(format_value(0.1 + 0.2), "0.3");
}

/// The charts' text comes from the embedded DejaVu Sans, whatever the machine has installed:
/// the bytes name it, and plotters measures a label with its metrics (a different font, or a
/// font from the system, gives other sizes).
#[test]
fn text_is_set_in_the_embedded_dejavu_sans() {
    let name = b"DejaVu Sans";
    assert!(
        font::FONT_TTF.windows(name.len()).any(|w| w == name),
        "the embedded font is not DejaVu Sans"
    );
    register_font().unwrap();
    let measured = |size: u32, text: &str| (FONT, size).into_font().box_size(text).unwrap();
    // DejaVu Sans's advances and heights at these pixel sizes, as plotters lays them out.
    assert_eq!(measured(24, "lights listed ÷ lights reaching"), (302, 19));
    assert_eq!(measured(13, "0.05"), (24, 10));
}
