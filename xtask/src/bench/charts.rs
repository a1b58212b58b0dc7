//! The benchmark's charts: PNG plots rendered from the CSV records ([`CellRecord`]).
//!
//! For each scene, resolution and MSAA count it draws the GPU time of each path against the light
//! count (light culling, forward shading and the whole frame, side by side) and the cull
//! efficiency of each culling method against the light count. Charts are rendered by plotters
//! into a pixel buffer and saved with `image`; their text uses the font embedded in the binary
//! ([`font`]), so they look the same on every machine. The axes are in [`axes`].

mod axes;
mod font;
pub(crate) mod scale;
#[cfg(test)]
mod tests;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context as _, Result};
use plotters::coord::Shift;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use self::axes::{CountAxis, efficiency_axis, format_value, log_axis};
pub(crate) use self::font::{FONT, register_font};
use super::record::CellRecord;

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
    let panels =
        GPU_PANELS.map(|(title, value)| (title, plotted(&lines, &records, by_lights, value, true)));
    if panels.iter().all(|(_, series)| series.is_empty()) {
        return Ok(false);
    }
    let x = CountAxis::lights(&records);
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
    let series = plotted(&lines, &records, by_lights, |r| r.cull_efficiency, false);
    let Some(y) = efficiency_axis(&series) else {
        return Ok(false);
    };
    let x = CountAxis::lights(&records);
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

/// A line with the points it has in one panel: (x, value), sorted by x.
type Series<'a> = (&'a Line, Vec<(f64, f64)>);

/// The light count of a record, the x of most charts.
fn by_lights(record: &CellRecord) -> Option<f64> {
    Some(f64::from(record.lights))
}

/// The points `(x, value)` of each line for one panel's `value`; missing, non-finite (and on a log axis,
/// non-positive) values are left out, and so are lines left without points.
fn plotted<'a>(
    lines: &'a [Line],
    records: &[&CellRecord],
    x: Figure,
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
                .filter_map(|r| Some((x(r)?, value(r).filter(plottable)?)))
                .collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            (line, points)
        })
        .filter(|(_, points)| !points.is_empty())
        .collect()
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

/// Writes a title at the top of `area` and returns the area below it.
fn titled<'a>(area: &Area<'a>, title: &str) -> Result<Area<'a>> {
    Ok(area.titled(title, (FONT, 24))?)
}

/// One plot: log-2 counts (`x`) across, `y` up, a line with markers per series.
fn draw_panel<Y>(
    area: &Area<'_>,
    title: &str,
    x: &CountAxis,
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
        .x_desc(x.desc)
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
