//! The benchmark's charts: PNG plots rendered from the CSV records ([`CellRecord`]).
//!
//! For each scene, resolution and MSAA count it draws the GPU time of each path against the light
//! count (light culling, forward shading and the whole frame, side by side) and the cull
//! efficiency of each culling method against the light count. Charts are rendered by plotters
//! into a pixel buffer and saved with `image`; text needs a TrueType font from the system
//! (`fonts-dejavu-core` on Debian), loaded at runtime so the build needs no font libraries.

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use anyhow::{Context as _, Result};
use plotters::coord::Shift;
use plotters::coord::combinators::WithKeyPoints;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::record::CellRecord;

/// The family name the loaded font is registered under (plotters' default family).
pub(crate) const FONT: &str = "sans-serif";

/// Where a sans-serif TrueType font usually lives: Debian/Ubuntu, Fedora, Arch, macOS.
pub(crate) const FONT_PATHS: &[&str] = &[
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    "/usr/share/fonts/truetype/liberation2/LiberationSans-Regular.ttf",
    "/usr/share/fonts/dejavu-sans-fonts/DejaVuSans.ttf",
    "/usr/share/fonts/liberation-sans/LiberationSans-Regular.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/liberation/LiberationSans-Regular.ttf",
    "/Library/Fonts/Arial.ttf",
    "/System/Library/Fonts/Supplemental/Arial.ttf",
];

/// Pixel sizes: one plot panel, the legend column on the right, the whole chart's height.
const PANEL_WIDTH: u32 = 560;
const LEGEND_WIDTH: u32 = 240;
const CHART_HEIGHT: u32 = 600;

/// Distinct line colours (Tableau 10); charts with more paths continue with `Palette99`.
const COLORS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Writes every chart for `records` into `out_dir`; returns the PNG paths written.
///
/// Per (scene, resolution, MSAA) group: `gpu_<scene>_<w>x<h>_msaa<m>.png` and, when the group has
/// cull efficiencies, `cull_efficiency_<scene>_<w>x<h>_msaa<m>.png`. A chart without any data is
/// skipped; empty `records` write nothing.
pub fn write_charts(records: &[CellRecord], out_dir: &Path) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let matrix: Vec<CellRecord> = records
        .iter()
        .filter(|r| !r.is_shadow_cell())
        .cloned()
        .collect();
    for (group, records) in groups(&matrix) {
        let gpu = out_dir.join(format!("gpu_{}.png", group.file_stem()));
        if write_gpu_chart(&group, &records, &gpu)? {
            written.push(gpu);
        }
        let efficiency = out_dir.join(format!("cull_efficiency_{}.png", group.file_stem()));
        if write_efficiency_chart(&group, &records, &efficiency)? {
            written.push(efficiency);
        }
    }
    Ok(written)
}

/// The records of one chart: a scene at one resolution and MSAA count.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
struct Group {
    scene: String,
    width: u32,
    height: u32,
    msaa: u32,
}

impl Group {
    fn of(record: &CellRecord) -> Self {
        Self {
            scene: record.scene.clone(),
            width: record.width,
            height: record.height,
            msaa: record.msaa,
        }
    }

    fn file_stem(&self) -> String {
        let scene = sanitize(&self.scene);
        format!("{scene}_{}x{}_msaa{}", self.width, self.height, self.msaa)
    }

    fn describe(&self) -> String {
        let Self {
            scene,
            width,
            height,
            msaa,
        } = self;
        format!("{scene}, {width}×{height}, MSAA {msaa}")
    }
}

fn groups(records: &[CellRecord]) -> BTreeMap<Group, Vec<&CellRecord>> {
    let mut groups = BTreeMap::<Group, Vec<&CellRecord>>::new();
    for record in records {
        groups.entry(Group::of(record)).or_default().push(record);
    }
    groups
}

/// A scene name made safe for a file name: ASCII letters, digits, `-` and `_`.
fn sanitize(scene: &str) -> String {
    let safe: String = scene
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if safe.is_empty() {
        "scene".into()
    } else {
        safe
    }
}

/// The figure a panel plots, taken from a record.
type Figure = fn(&CellRecord) -> Option<f64>;

/// The panels of the GPU-time chart, left to right.
const GPU_PANELS: [(&str, Figure); 3] = [
    ("light culling", |r| r.cull_median_ms),
    ("forward shading", |r| r.forward_median_ms),
    ("whole frame (all passes)", |r| Some(r.gpu_total_median_ms)),
];

/// The GPU-time chart of a group: culling, forward and whole frame against the light count.
/// Only untiled paths and tile 16 are drawn (the other tile sizes would clutter it). Returns
/// whether a chart was written.
fn write_gpu_chart(group: &Group, records: &[&CellRecord], path: &Path) -> Result<bool> {
    let records: Vec<&CellRecord> = records
        .iter()
        .copied()
        .filter(|r| r.tile == 0 || r.tile == 16)
        .collect();
    let lines = lines(&records);
    let panels = GPU_PANELS.map(|(title, value)| (title, plotted(&lines, &records, value, true)));
    if panels.iter().all(|(_, series)| series.is_empty()) {
        return Ok(false);
    }
    let x = LightAxis::of(&records);
    let title = format!("{}: GPU timestamps, median", group.describe());
    let size = (3 * PANEL_WIDTH + LEGEND_WIDTH, CHART_HEIGHT);
    render_png(path, size, |root| {
        let (plots, legend) = titled(root, &title)?.split_horizontally(3 * PANEL_WIDTH);
        for ((title, series), area) in panels.iter().zip(plots.split_evenly((1, 3))) {
            match log_axis(series) {
                Some(y) => draw_panel(&area, title, &x, y, "median GPU ms", series)?,
                None => draw_empty_panel(&area, title)?,
            }
        }
        draw_legend(&legend, &lines)
    })?;
    Ok(true)
}

/// The cull-efficiency chart of a group: lights listed ÷ lights reaching against the light count,
/// one line per culling method (without scalarization, which lists the same lights). Returns
/// whether a chart was written.
fn write_efficiency_chart(group: &Group, records: &[&CellRecord], path: &Path) -> Result<bool> {
    let records: Vec<&CellRecord> = records
        .iter()
        .copied()
        .filter(|r| !r.scalarize && r.cull_efficiency.is_some())
        .collect();
    let lines = lines(&records);
    let series = plotted(&lines, &records, |r| r.cull_efficiency, false);
    let Some(y) = efficiency_axis(&series) else {
        return Ok(false);
    };
    let x = LightAxis::of(&records);
    let title = format!("{}: cull efficiency (1 = exact)", group.describe());
    let size = (PANEL_WIDTH + PANEL_WIDTH / 2 + LEGEND_WIDTH, CHART_HEIGHT);
    render_png(path, size, |root| {
        let (plot, legend) = titled(root, &title)?.split_horizontally(size.0 - LEGEND_WIDTH);
        let y_desc = "lights listed ÷ lights reaching";
        draw_panel(&plot, "culling methods", &x, y, y_desc, &series)?;
        draw_legend(&legend, &lines)
    })?;
    Ok(true)
}

/// One path of a chart, as its legend shows it.
#[derive(Debug, Clone)]
struct Line {
    label: String,
    color: RGBColor,
    /// Scalarized variants get hollow markers.
    hollow: bool,
}

/// The lines of a chart, one per path label in `records`, in a stable order (path, tile,
/// scalarization) so that a label keeps its colour in every panel.
fn lines(records: &[&CellRecord]) -> Vec<Line> {
    let mut keys: Vec<_> = records
        .iter()
        .map(|r| (path_rank(&r.path), r.tile, r.scalarize, r.label()))
        .collect();
    keys.sort();
    keys.dedup();
    keys.into_iter()
        .enumerate()
        .map(|(i, (_, _, scalarize, label))| Line {
            label,
            color: color(i),
            hollow: scalarize,
        })
        .collect()
}

fn path_rank(path: &str) -> usize {
    let order = ["naive", "naive-prez", "tiled", "2.5d", "clustered"];
    order.iter().position(|p| *p == path).unwrap_or(order.len())
}

fn color(index: usize) -> RGBColor {
    COLORS.get(index).copied().unwrap_or_else(|| {
        let (r, g, b) = Palette99::pick(index).rgb();
        RGBColor(r, g, b)
    })
}

/// A line with the points it has in one panel: (light count, value), sorted by light count.
type Series<'a> = (&'a Line, Vec<(f64, f64)>);

/// The points of each line for one panel's `value`; missing, non-finite (and on a log axis,
/// non-positive) values are left out, and so are lines left without points.
fn plotted<'a>(
    lines: &'a [Line],
    records: &[&CellRecord],
    value: impl Fn(&CellRecord) -> Option<f64>,
    log: bool,
) -> Vec<Series<'a>> {
    let plottable = |v: &f64| v.is_finite() && (!log || *v > 0.0);
    lines
        .iter()
        .map(|line| {
            let mut points: Vec<(f64, f64)> = records
                .iter()
                .filter(|r| r.label() == line.label)
                .filter_map(|r| Some((f64::from(r.lights), value(r).filter(plottable)?)))
                .collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            (line, points)
        })
        .filter(|(_, points)| !points.is_empty())
        .collect()
}

/// The light-count axis of a chart: log 2, ticked at the counts present (thinned out if many).
#[derive(Debug, Clone)]
struct LightAxis {
    range: Range<f64>,
    ticks: Vec<f64>,
}

impl LightAxis {
    fn of(records: &[&CellRecord]) -> Self {
        let mut counts: Vec<u32> = records.iter().map(|r| r.lights.max(1)).collect();
        counts.sort_unstable();
        counts.dedup();
        let step = counts.len().div_ceil(12).max(1);
        let ticks = counts.iter().step_by(step).map(|&c| f64::from(c)).collect();
        let (lo, hi) = match (counts.first(), counts.last()) {
            (Some(&lo), Some(&hi)) => (f64::from(lo), f64::from(hi)),
            _ => (1.0, 1.0),
        };
        Self {
            range: lo / 1.25..hi * 1.25,
            ticks,
        }
    }

    fn coord(&self) -> WithKeyPoints<LogCoord<f64>> {
        let range = self.range.clone();
        range
            .log_scale()
            .base(2.0)
            .with_key_points(self.ticks.clone())
    }
}

/// Log-10 value axis over every point of `series`, ticked at 1, 2, 5 × 10^k; `None` without points.
fn log_axis(series: &[Series<'_>]) -> Option<WithKeyPoints<LogCoord<f64>>> {
    let (lo, hi) = value_bounds(series)?;
    let (range, ticks) = log_ticks(lo, hi);
    Some(range.log_scale().with_key_points(ticks))
}

/// Linear efficiency axis from 1 (exact lists) to a little above the largest value.
fn efficiency_axis(series: &[Series<'_>]) -> Option<RangedCoordf64> {
    let (lo, hi) = value_bounds(series)?;
    let top = (hi * 1.05).max(lo.min(1.0) + 0.1);
    Some((lo.min(1.0)..top).into())
}

fn value_bounds(series: &[Series<'_>]) -> Option<(f64, f64)> {
    let values = series
        .iter()
        .flat_map(|(_, points)| points.iter().map(|p| p.1));
    values.fold(None, |bounds, v| match bounds {
        None => Some((v, v)),
        Some((lo, hi)) => Some((f64::min(lo, v), f64::max(hi, v))),
    })
}

/// A log range covering `lo..=hi` (positive) with some margin, from one 1-2-5 tick to another,
/// and the ticks in it: 1, 2, 5 × 10^k, or every integer mantissa when that gives fewer than three,
/// or only the powers of ten when it gives more than ten.
fn log_ticks(lo: f64, hi: f64) -> (Range<f64>, Vec<f64>) {
    let (start, end) = (nice_at_or_below(lo / 1.1), nice_at_or_above(hi * 1.1));
    let in_range = |v: &f64| *v >= start * (1.0 - 1e-9) && *v <= end * (1.0 + 1e-9);
    let ticks = |mantissas: &[f64]| -> Vec<f64> {
        let decades = start.log10().floor() as i32..=end.log10().ceil() as i32;
        decades
            .flat_map(|k| mantissas.iter().map(move |m| m * 10f64.powi(k)))
            .filter(in_range)
            .collect()
    };
    let mut chosen = ticks(&[1.0, 2.0, 5.0]);
    if chosen.len() < 3 {
        chosen = ticks(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]);
    } else if chosen.len() > 10 {
        chosen = ticks(&[1.0]);
    }
    (start..end, chosen)
}

fn nice_at_or_below(v: f64) -> f64 {
    let decade = 10f64.powf(v.log10().floor());
    let m = [5.0, 2.0, 1.0]
        .into_iter()
        .find(|m| m * decade <= v * (1.0 + 1e-9));
    m.unwrap_or(1.0) * decade
}

fn nice_at_or_above(v: f64) -> f64 {
    let decade = 10f64.powf(v.log10().floor());
    let m = [1.0, 2.0, 5.0]
        .into_iter()
        .find(|m| m * decade >= v * (1.0 - 1e-9));
    m.unwrap_or(10.0) * decade
}

/// A tick label without float noise or trailing zeros (0.05, 0.2, 1.5, 20).
fn format_value(v: f64) -> String {
    let s = format!("{v:.6}");
    s.trim_end_matches('0').trim_end_matches('.').to_owned()
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

/// Draws a chart into an RGB buffer and saves it as a PNG.
fn render_png(
    path: &Path,
    (width, height): (u32, u32),
    draw: impl FnOnce(&Area<'_>) -> Result<()>,
) -> Result<()> {
    register_font()?;
    let mut buffer = vec![0u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (width, height)).into_drawing_area();
        root.fill(&WHITE)?;
        draw(&root).with_context(|| format!("drawing {}", path.display()))?;
        root.present()?;
    }
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    image::RgbImage::from_raw(width, height, buffer)
        .context("chart buffer of the wrong size")?
        .save_with_format(path, image::ImageFormat::Png)
        .with_context(|| format!("writing {}", path.display()))
}

/// Loads the first font of [`FONT_PATHS`] and registers it for plotters, once per process.
pub(crate) fn register_font() -> Result<()> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    let registered = REGISTERED.get_or_init(|| {
        for path in FONT_PATHS {
            if let Ok(bytes) = std::fs::read(path) {
                // plotters keeps fonts for the whole process; this runs once.
                let bytes: &'static [u8] = Vec::leak(bytes);
                if plotters::style::register_font(FONT, FontStyle::Normal, bytes).is_ok() {
                    return Ok(());
                }
            }
        }
        Err(format!(
            "the benchmark charts need a TrueType font and none was found (looked for {}); \
             install one, e.g. `apt-get install fonts-dejavu-core`",
            FONT_PATHS.join(", ")
        ))
    });
    registered.clone().map_err(anyhow::Error::msg)
}

/// Writes a title at the top of `area` and returns the area below it.
fn titled<'a>(area: &Area<'a>, title: &str) -> Result<Area<'a>> {
    Ok(area.titled(title, (FONT, 24))?)
}

/// One plot: log-2 light counts across, `y` up, a line with markers per series.
fn draw_panel<Y>(
    area: &Area<'_>,
    title: &str,
    x: &LightAxis,
    y: Y,
    y_desc: &str,
    series: &[Series<'_>],
) -> Result<()>
where
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut chart = ChartBuilder::on(area)
        .caption(title, (FONT, 18))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d(x.coord(), y)?;
    chart
        .configure_mesh()
        .x_desc("lights")
        .y_desc(y_desc)
        .x_label_formatter(&|v| format!("{}", v.round()))
        .y_label_formatter(&|v| format_value(*v))
        .max_light_lines(4)
        .label_style((FONT, 13))
        .axis_desc_style((FONT, 15))
        .draw()?;
    for (line, points) in series {
        chart.draw_series(LineSeries::new(
            points.iter().copied(),
            line.color.stroke_width(2),
        ))?;
        chart.draw_series(points.iter().map(|&p| marker(p, line)))?;
    }
    Ok(())
}

/// A panel with nothing to plot: its title and a note.
fn draw_empty_panel(area: &Area<'_>, title: &str) -> Result<()> {
    let area = area.titled(title, (FONT, 18))?;
    let (width, height) = area.dim_in_pixel();
    let center = Pos::new(HPos::Center, VPos::Center);
    let grey = BLACK.mix(0.6);
    let style = TextStyle::from((FONT, 16).into_font())
        .color(&grey)
        .pos(center);
    area.draw(&Text::new(
        "no data",
        (width as i32 / 2, height as i32 / 2),
        style,
    ))?;
    Ok(())
}

fn marker<C>(at: C, line: &Line) -> Circle<C, i32> {
    let style = if line.hollow {
        line.color.stroke_width(2)
    } else {
        line.color.filled()
    };
    Circle::new(at, 4, style)
}

/// The legend: one row per line, in the column right of the plots.
fn draw_legend(area: &Area<'_>, lines: &[Line]) -> Result<()> {
    let style = TextStyle::from((FONT, 15).into_font()).pos(Pos::new(HPos::Left, VPos::Center));
    for (i, line) in lines.iter().enumerate() {
        let y = 60 + 26 * i as i32;
        area.draw(&PathElement::new(
            [(8, y), (40, y)],
            line.color.stroke_width(2),
        ))?;
        area.draw(&marker((24, y), line))?;
        area.draw(&Text::new(line.label.clone(), (50, y), style.clone()))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
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
    const EFFICIENCY_SIZE: (u32, u32) =
        (PANEL_WIDTH + PANEL_WIDTH / 2 + LEGEND_WIDTH, CHART_HEIGHT);

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
}
