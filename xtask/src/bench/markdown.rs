//! The Markdown report of a run: a table per scene, size and MSAA, and the comparisons the
//! benchmark exists for (Forward+ against naive forward, scalarized against not, shadows
//! against none).

use std::collections::BTreeMap;
use std::fmt::Write as _;

use super::record::{CellRecord, ms};

fn med_p90(m: Option<f64>, p: Option<f64>) -> String {
    match (m, p) {
        (Some(m), Some(p)) => format!("{m:.3} ({p:.3})"),
        _ => "–".into(),
    }
}

fn kib(b: u64) -> String {
    match b {
        0 => "–".into(),
        b if b < 10 * 1024 => format!("{:.2}", b as f64 / 1024.0),
        b => format!("{:.0}", b as f64 / 1024.0),
    }
}

type GroupKey = (String, u32, u32, u32);

fn groups(records: &[CellRecord]) -> BTreeMap<GroupKey, Vec<&CellRecord>> {
    let mut g: BTreeMap<GroupKey, Vec<&CellRecord>> = BTreeMap::new();
    for r in records {
        g.entry((r.scene.clone(), r.width, r.height, r.msaa))
            .or_default()
            .push(r);
    }
    g
}

/// The whole report: `meta` (adapter, command, calibration) first, then the tables of the light
/// matrix, then the shadow and decal axes.
pub fn report(meta: &str, all: &[CellRecord]) -> String {
    let matrix: Vec<CellRecord> = all
        .iter()
        .filter(|r| !r.is_shadow_cell() && r.decals == 0)
        .cloned()
        .collect();
    let records = &matrix[..];
    let mut out = String::new();
    out += meta;
    out += "\n";
    out += &speedups(records);
    out += &scalarization(records);
    out += &super::shadows::markdown(all);
    out += &super::decals::markdown(all);
    out += &super::scale::markdown(records);
    for ((scene, w, h, msaa), rows) in groups(records) {
        let _ = writeln!(out, "\n### {scene}, {w}×{h}, MSAA {msaa}\n");
        out += "GPU ms, median (p90); floor and ratio for the culling pass; CPU = build + \
                compile + encode the frame graph, median ms (upload: uniforms and culling items); efficiency = lights listed ÷ lights \
                reaching a sample.\n\n";
        out += "| path | lights | frames | pre-Z | culling | floor µs | ÷ floor | forward | \
                tonemap | total | CPU graph (upload) ms | grid KiB | index KiB used / alloc | efficiency | \
                reach | dropped | note |\n";
        out += "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
        for r in rows {
            let _ = writeln!(
                out,
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.3} | {:.3} ({:.3}) | {} | {} / {} | {} | {} | {} | {} |",
                r.label(),
                r.lights,
                r.frames,
                ms(r.prez_median_ms),
                med_p90(r.cull_median_ms, r.cull_p90_ms),
                r.cull_floor_us
                    .map_or_else(|| "–".into(), |f| format!("{f:.1}")),
                r.cull_ratio_to_floor()
                    .map_or_else(|| "–".into(), |x| format!("{x:.1}")),
                med_p90(r.forward_median_ms, r.forward_p90_ms),
                ms(r.tonemap_median_ms),
                r.gpu_total_median_ms,
                r.cpu_graph_median_ms,
                r.cpu_upload_median_ms,
                kib(r.grid_bytes),
                kib(r.index_bytes_used),
                kib(r.index_bytes_allocated),
                r.cull_efficiency
                    .map_or_else(|| "–".into(), |e| format!("{e:.2}")),
                r.lights_reaching_mean
                    .map_or_else(|| "–".into(), |e| format!("{e:.1}")),
                r.dropped,
                r.note
            );
        }
    }
    out
}

fn find<'a>(
    records: &'a [CellRecord],
    like: &CellRecord,
    path: &str,
    tile: u32,
    scalarize: bool,
) -> Option<&'a CellRecord> {
    records.iter().find(|r| {
        r.scene == like.scene
            && (r.width, r.height, r.msaa, r.lights)
                == (like.width, like.height, like.msaa, like.lights)
            && r.path == path
            && r.tile == tile
            && r.scalarize == scalarize
    })
}

/// Forward shading pass of naive forward (with pre-Z, so both shade each sample once) over
/// that of each culled path, same frame settings.
fn speedups(records: &[CellRecord]) -> String {
    let mut out = String::from(
        "\n### Forward shading: naive against culled\n\nForward-pass GPU median of naive-prez ÷ \
         that of the culled path (same scene, size, MSAA and lights; scalarize off). Whole frame \
         in brackets (naive without pre-Z ÷ culled path, all passes).\n\n| scene | size | MSAA | \
         lights | tiled 16 | 2.5d 16 | clustered |\n|---|---|---:|---:|---:|---:|---:|\n",
    );
    let mut any = false;
    for naive in records
        .iter()
        .filter(|r| r.path == "naive-prez" && r.frames > 0)
    {
        let ratio = |path: &str, tile: u32| -> String {
            let Some(culled) = find(records, naive, path, tile, false) else {
                return "–".into();
            };
            let fwd = match (naive.forward_median_ms, culled.forward_median_ms) {
                (Some(a), Some(b)) if b > 0.0 => format!("{:.1}×", a / b),
                _ => "–".into(),
            };
            let frame = find(records, naive, "naive", 0, false)
                .filter(|n| n.frames > 0 && culled.gpu_total_median_ms > 0.0)
                .map(|n| {
                    format!(
                        " ({:.1}×)",
                        n.gpu_total_median_ms / culled.gpu_total_median_ms
                    )
                })
                .unwrap_or_default();
            fwd + &frame
        };
        any = true;
        let _ = writeln!(
            out,
            "| {} | {}×{} | {} | {} | {} | {} | {} |",
            naive.scene,
            naive.width,
            naive.height,
            naive.msaa,
            naive.lights,
            ratio("tiled", 16),
            ratio("2.5d", 16),
            ratio("clustered", 0)
        );
    }
    if any { out } else { String::new() }
}

/// Culling pass with subgroup operations over without, same cell.
fn scalarization(records: &[CellRecord]) -> String {
    let mut out = String::from(
        "\n### Scalarization: culling pass, scalarized ÷ plain (below 1 is a gain)\n\n| scene | \
         size | MSAA | lights | path | plain ms | scalarized ms | ratio | forward ratio |\n\
         |---|---|---:|---:|---|---:|---:|---:|---:|\n",
    );
    let mut any = false;
    for s in records.iter().filter(|r| r.scalarize) {
        let Some(p) = find(records, s, &s.path, s.tile, false) else {
            continue;
        };
        let (Some(a), Some(b)) = (p.cull_median_ms, s.cull_median_ms) else {
            continue;
        };
        let fwd = match (p.forward_median_ms, s.forward_median_ms) {
            (Some(x), Some(y)) if x > 0.0 => format!("{:.2}", y / x),
            _ => "–".into(),
        };
        any = true;
        let _ = writeln!(
            out,
            "| {} | {}×{} | {} | {} | {} | {a:.3} | {b:.3} | {:.2} | {fwd} |",
            s.scene,
            s.width,
            s.height,
            s.msaa,
            s.lights,
            p.label(),
            b / a
        );
    }
    if any { out } else { String::new() }
}
