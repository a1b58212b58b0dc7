//! The benchmark's scene-size axis: generated cities of several sizes (`--scene city:N`), and
//! the report section that shows how each path's CPU and GPU cost grows with them.

use std::fmt::Write as _;

use super::record::{CellRecord, ms};

/// The records of generated cities (scene `city:N`) of the light matrix, by path then size.
pub(super) fn city_records(records: &[CellRecord]) -> Vec<&CellRecord> {
    let mut cities: Vec<&CellRecord> = records
        .iter()
        .filter(|r| r.scene.starts_with("city:") && r.instances > 0 && !r.is_shadow_cell())
        .collect();
    cities.sort_by(|a, b| {
        (a.label(), a.msaa, a.lights, a.instances).cmp(&(b.label(), b.msaa, b.lights, b.instances))
    });
    cities
}

/// The section: per path and city size, the CPU per frame in its three parts and the GPU time
/// of the geometry passes and the frame; empty without city records.
pub(super) fn markdown(records: &[CellRecord]) -> String {
    let cities = city_records(records);
    if cities.is_empty() {
        return String::new();
    }
    let mut out = String::from(
        "\n## Cost against scene size (generated city)\n\nThe same street camera over cities of \
         growing size (`--scene city:N`). Drawn = the opaque and masked draws (one per instance \
         primitive) the GPU culling kept in the last timed frame, plus every blended draw (those \
         are culled against the frustum on the CPU, uncounted), or all with culling off. CPU = the renderer's CPU per frame: prepare (uniforms, \
         culling items, shadow planning), record (build, compile and encode the frame graph) and \
         submit, medians in ms. GPU = timestamps, median ms; occlusion = two-phase occlusion \
         culling's second phase (depth pyramid, late test, late pre-Z; `off` with \
         `--no-occlusion`); geometry = pre-Z + occlusion + G-buffer (deferred paths) or \
         forward.\n\n",
    );
    out += "| path | MSAA | lights | instances | triangles | drawn | CPU frame | prepare | \
            record | submit | pre-Z | occlusion | G-buffer | forward | geometry | GPU total |\n";
    out += "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for &r in &cities {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {:.3} | {:.3} | {:.3} | {:.3} | {} | {} | {} | {} | {} | {:.3} |",
            r.label(),
            r.msaa,
            r.lights,
            r.instances,
            r.triangles,
            r.draws_visible.map_or_else(
                || format!("all {}", r.draws),
                |v| format!("{v} of {}", r.draws)
            ),
            r.cpu_frame_ms(),
            r.cpu_upload_median_ms,
            r.cpu_graph_median_ms,
            r.cpu_submit_median_ms,
            ms(r.prez_median_ms),
            r.occlusion_median_ms.map_or_else(
                || "off".to_string(),
                |o| format!("{:.3}", o + r.prez_late_median_ms.unwrap_or(0.0))
            ),
            ms(r.gbuffer_median_ms),
            ms(r.forward_median_ms),
            ms(r.geometry_median_ms()),
            r.gpu_total_median_ms,
        );
    }
    out + &edits_markdown(&cities)
}

/// The cost of editing each city by handle (`bench::edits`): empty when no record has it.
fn edits_markdown(cities: &[&CellRecord]) -> String {
    let edited: Vec<&&CellRecord> = cities
        .iter()
        .filter(|r| r.edit_add_median_us.is_some())
        .collect();
    if edited.is_empty() {
        return String::new();
    }
    let mut out = String::from(
        "\nEditing the scene by handle between frames: 100 instances added (their draws \
         appended), moved and removed, then 100 added again into the removed slots, each edit \
         timed alone on the CPU (µs; add: median and most); a frame rendered after every tenth \
         edit, and the CPU of those frames (ms, median; the passes catch up with the edits \
         there). Then 20 rounds of streaming a mesh: a copy of the first instance's mesh added \
         (its vertices uploaded into the room the previous round gave back) and removed again, \
         each timed alone (µs, median).\n\n| path | MSAA | instances | add | add (most) | move \
         | remove | CPU frame after edits | add mesh | remove mesh |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let us = |v: Option<f64>| v.map_or_else(|| "–".into(), |v| format!("{v:.1}"));
    for r in edited {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.label(),
            r.msaa,
            r.instances,
            us(r.edit_add_median_us),
            us(r.edit_add_max_us),
            us(r.edit_move_median_us),
            us(r.edit_remove_median_us),
            ms(r.edit_frame_cpu_median_ms),
            us(r.edit_mesh_add_median_us),
            us(r.edit_mesh_remove_median_us),
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn city(instances: u64, path: &str, cpu: f64) -> CellRecord {
        CellRecord {
            scene: format!("city:{instances}"),
            path: path.into(),
            instances,
            triangles: instances * 100,
            msaa: 4,
            lights: 4096,
            cpu_upload_median_ms: cpu,
            cpu_graph_median_ms: 2.0 * cpu,
            cpu_submit_median_ms: 0.5,
            prez_median_ms: Some(1.0),
            forward_median_ms: Some(2.0),
            gpu_total_median_ms: 4.0,
            ..Default::default()
        }
    }

    #[test]
    fn the_section_lists_cities_by_path_then_size_and_sums_the_cpu() {
        let records = [
            CellRecord {
                edit_add_median_us: Some(12.5),
                edit_add_max_us: Some(40.0),
                edit_move_median_us: Some(3.3),
                edit_remove_median_us: Some(1.0),
                edit_frame_cpu_median_ms: Some(0.9),
                edit_mesh_add_median_us: Some(30.0),
                ..city(10_000, "tiled", 1.0)
            },
            city(1_000, "tiled", 0.1),
            CellRecord {
                scene: "courtyard".into(),
                ..city(5, "tiled", 9.0)
            },
        ];
        let md = markdown(&records);
        let rows: Vec<&str> = md.lines().filter(|l| l.starts_with("| tiled")).collect();
        assert_eq!(rows.len(), 3, "{md}");
        assert!(
            rows[0].contains("| 1000 | 100000 | all 0 | 0.800 |"),
            "{}",
            rows[0]
        );
        assert!(
            rows[1].contains("| 10000 | 1000000 | all 0 | 3.500 |"),
            "{}",
            rows[1]
        );
        assert!(rows[1].ends_with("| 3.000 | 4.000 |"), "{}", rows[1]);
        assert!(
            rows[1].contains("| off |"),
            "no occlusion timings: {}",
            rows[1]
        );
        // Only the city whose edits were timed has an edit row.
        assert_eq!(
            rows[2],
            "| tiled | 4 | 10000 | 12.5 | 40.0 | 3.3 | 1.0 | 0.900 | 30.0 | – |"
        );
        assert_eq!(markdown(&records[2..]), "");
    }
}
