//! The decal axis of the benchmark (`--decals 0,256,1024,4096`): each cell of the light matrix
//! measured again with that many procedural decals on the scene's surfaces (the built-in
//! scorch, stain and sign materials, placed by area with the run's seed), and its report
//! section: forward and culling cost against the same frame without decals.

use std::fmt::Write as _;

use renderer::decals::{DecalSet, procedural};
use renderer::demo::scatter_decals;
use renderer::scene::Scene;

use super::record::{CellRecord, ms};

/// `count` seeded decals on `scene` with the built-in materials.
pub fn decal_set(scene: &Scene, count: u32, seed: u64) -> DecalSet {
    let materials = procedural::materials();
    let decals = scatter_decals(scene, count as usize, materials.len(), seed);
    DecalSet { materials, decals }
}

/// The same cell without decals.
fn baseline<'a>(records: &'a [CellRecord], r: &CellRecord) -> Option<&'a CellRecord> {
    records.iter().find(|b| {
        b.decals == 0
            && !b.is_shadow_cell()
            && b.scene == r.scene
            && (b.width, b.height, b.msaa, b.tile, b.lights)
                == (r.width, r.height, r.msaa, r.tile, r.lights)
            && (&b.path, b.scalarize, b.brute_force) == (&r.path, r.scalarize, r.brute_force)
    })
}

/// `new` over `old` as a signed percentage, or `–`.
fn change(new: Option<f64>, old: Option<f64>) -> String {
    match (new, old) {
        (Some(n), Some(o)) if o > 0.0 => format!("{:+.1}%", 100.0 * (n - o) / o),
        _ => "–".into(),
    }
}

/// The decal section of `bench.md` (empty without decal cells).
pub fn markdown(records: &[CellRecord]) -> String {
    let rows: Vec<&CellRecord> = records.iter().filter(|r| r.decals > 0).collect();
    if rows.is_empty() {
        return String::new();
    }
    let mut out = String::from(
        "\n### Decals\n\nGPU ms per frame, median (p90). Each row against the same cell \
         without decals: forward and culling change. Dropped = list entries the index list \
         could not hold (0: every decal applied).\n\n| path | size | MSAA | lights | decals | \
         culling | forward | total | forward vs 0 decals | culling vs 0 decals | dropped |\n\
         |---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in &rows {
        let base = baseline(records, r);
        let _ = writeln!(
            out,
            "| {} | {}×{} | {} | {} | {} | {} ({}) | {} ({}) | {:.3} | {} | {} | {} |",
            r.label(),
            r.width,
            r.height,
            r.msaa,
            r.lights,
            r.decals,
            ms(r.cull_median_ms),
            ms(r.cull_p90_ms),
            ms(r.forward_median_ms),
            ms(r.forward_p90_ms),
            r.gpu_total_median_ms,
            change(r.forward_median_ms, base.and_then(|b| b.forward_median_ms)),
            change(r.cull_median_ms, base.and_then(|b| b.cull_median_ms)),
            r.dropped,
        );
    }
    out += &goal(records, &rows);
    out
}

/// The goal: 1,024 decals add at most 15% to the forward pass; 4,096 drop nothing.
fn goal(records: &[CellRecord], rows: &[&CellRecord]) -> String {
    let mut out = String::new();
    for r in rows.iter().filter(|r| r.decals == 1024) {
        let Some(b) = baseline(records, r) else {
            continue;
        };
        let _ = writeln!(
            out,
            "\n{} {}×{} MSAA {}, {} lights: 1,024 decals change the forward pass by {} (goal \
             ≤ +15%).",
            r.label(),
            r.width,
            r.height,
            r.msaa,
            r.lights,
            change(r.forward_median_ms, b.forward_median_ms)
        );
    }
    let most = rows.iter().map(|r| r.decals).max().unwrap_or(0);
    let dropped: u32 = rows
        .iter()
        .filter(|r| r.decals == most)
        .map(|r| r.dropped)
        .sum();
    let _ = writeln!(
        out,
        "\n{most} decals per view: {dropped} list entries dropped over every cell (goal 0)."
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(decals: u32, forward: f64) -> CellRecord {
        CellRecord {
            scene: "demo".into(),
            width: 1920,
            height: 1080,
            msaa: 4,
            path: "clustered".into(),
            tile: 16,
            lights: 4096,
            decals,
            frames: 10,
            forward_median_ms: Some(forward),
            cull_median_ms: Some(1.0),
            ..Default::default()
        }
    }

    #[test]
    fn rows_compare_with_the_cell_without_decals_and_state_the_goal() {
        let records = [record(0, 10.0), record(1024, 11.0), record(4096, 13.0)];
        let md = markdown(&records);
        assert!(md.contains("| 1024 |") && md.contains("+10.0%"), "{md}");
        assert!(md.contains("+30.0%"), "{md}");
        assert!(
            md.contains("1,024 decals change the forward pass by +10.0%"),
            "{md}"
        );
        assert!(
            md.contains("4096 decals per view: 0 list entries dropped"),
            "{md}"
        );
        assert!(markdown(&records[..1]).is_empty());
    }
}
