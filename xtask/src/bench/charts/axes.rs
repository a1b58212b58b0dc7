//! The charts' axes: the light count (or a scene's instances) across (log 2, ticked at the counts measured) and the value
//! up (log 10 ticked at 1-2-5, or linear for cull efficiency), with tick labels free of float
//! noise.

use std::ops::Range;

use plotters::coord::combinators::WithKeyPoints;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::bench::record::CellRecord;

/// The count axis of a chart (lights, or a scene's instances): log 2, ticked at the counts
/// present (thinned out if many).
#[derive(Debug, Clone)]
pub(super) struct CountAxis {
    range: Range<f64>,
    ticks: Vec<f64>,
    /// What is counted, under the axis.
    pub(super) desc: &'static str,
}

impl CountAxis {
    /// The light counts of `records`.
    pub(super) fn lights(records: &[&CellRecord]) -> Self {
        Self::of(records.iter().map(|r| u64::from(r.lights)), "lights")
    }

    /// An axis over `counts`, described as `desc`.
    pub(super) fn of(counts: impl Iterator<Item = u64>, desc: &'static str) -> Self {
        let mut counts: Vec<u64> = counts.map(|c| c.max(1)).collect();
        counts.sort_unstable();
        counts.dedup();
        let step = counts.len().div_ceil(12).max(1);
        let ticks = counts.iter().step_by(step).map(|&c| c as f64).collect();
        let (lo, hi) = match (counts.first(), counts.last()) {
            (Some(&lo), Some(&hi)) => (lo as f64, hi as f64),
            _ => (1.0, 1.0),
        };
        Self {
            range: lo / 1.25..hi * 1.25,
            ticks,
            desc,
        }
    }

    pub(super) fn coord(&self) -> WithKeyPoints<LogCoord<f64>> {
        let range = self.range.clone();
        range
            .log_scale()
            .base(2.0)
            .with_key_points(self.ticks.clone())
    }
}

/// Log-10 value axis over every point of `series` (a line and its (x, value) points each),
/// ticked at 1, 2, 5 × 10^k; `None` without points.
pub(super) fn log_axis<L>(series: &[(L, Vec<(f64, f64)>)]) -> Option<WithKeyPoints<LogCoord<f64>>> {
    let (lo, hi) = value_bounds(series)?;
    let (range, ticks) = log_ticks(lo, hi);
    Some(range.log_scale().with_key_points(ticks))
}

/// Linear efficiency axis from 1 (exact lists) to a little above the largest value.
pub(super) fn efficiency_axis<L>(series: &[(L, Vec<(f64, f64)>)]) -> Option<RangedCoordf64> {
    let (lo, hi) = value_bounds(series)?;
    let top = (hi * 1.05).max(lo.min(1.0) + 0.1);
    Some((lo.min(1.0)..top).into())
}

fn value_bounds<L>(series: &[(L, Vec<(f64, f64)>)]) -> Option<(f64, f64)> {
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
pub(super) fn log_ticks(lo: f64, hi: f64) -> (Range<f64>, Vec<f64>) {
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
pub(super) fn format_value(v: f64) -> String {
    let s = format!("{v:.6}");
    s.trim_end_matches('0').trim_end_matches('.').to_owned()
}
