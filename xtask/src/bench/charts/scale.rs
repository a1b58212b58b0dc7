//! The scene-size chart: how a frame's CPU and GPU cost grows with the generated city's
//! instance count (`--scene city:N`), one line per path, log-log.

use std::path::{Path, PathBuf};

use anyhow::Result;

use super::{
    CHART_HEIGHT, CountAxis, Figure, LEGEND_WIDTH, PANEL_WIDTH, draw_empty_panel, draw_legend,
    draw_panel, lines, log_axis, plotted, render_png, titled,
};
use crate::bench::record::CellRecord;

/// The panels, left to right: the CPU per frame, the geometry passes, the whole GPU frame.
const PANELS: [(&str, Figure); 3] = [
    ("CPU per frame (prepare + record + submit)", |r| {
        Some(r.cpu_frame_ms())
    }),
    (
        "GPU geometry passes (pre-Z, occlusion, G-buffer or forward)",
        |r| r.geometry_median_ms(),
    ),
    ("GPU whole frame (all passes)", |r| {
        Some(r.gpu_total_median_ms)
    }),
];

/// The scene's instance count, the chart's x.
fn by_instances(record: &CellRecord) -> Option<f64> {
    (record.instances > 0).then_some(record.instances as f64)
}

/// Writes `scale.png` when `records` hold generated cities of two sizes or more; returns its
/// path.
pub(crate) fn write_scale_chart(records: &[CellRecord], out_dir: &Path) -> Result<Option<PathBuf>> {
    let cities: Vec<&CellRecord> = super::super::scale::city_records(records);
    let sizes: std::collections::BTreeSet<u64> = cities.iter().map(|r| r.instances).collect();
    if sizes.len() < 2 {
        return Ok(None);
    }
    let lines = lines(&cities);
    let panels =
        PANELS.map(|(title, value)| (title, plotted(&lines, &cities, by_instances, value, true)));
    let x = CountAxis::of(sizes.into_iter(), "instances in the city");
    let first = cities[0];
    let title = format!(
        "cost against scene size: generated city, {}×{}, MSAA {}, {} lights, median ms",
        first.width, first.height, first.msaa, first.lights
    );
    let path = out_dir.join("scale.png");
    let size = (3 * PANEL_WIDTH + LEGEND_WIDTH, CHART_HEIGHT);
    render_png(&path, size, |root| {
        let (plots, legend) = titled(root, &title)?.split_horizontally(3 * PANEL_WIDTH);
        for ((title, series), area) in panels.iter().zip(plots.split_evenly((1, 3))) {
            match log_axis(series) {
                Some(y) => draw_panel(&area, title, &x, y, "median ms", series)?,
                None => draw_empty_panel(&area, title)?,
            }
        }
        draw_legend(&legend, &lines)
    })?;
    Ok(Some(path))
}
