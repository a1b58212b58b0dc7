//! The visibility path against naive forward: the same scenes and cameras as the deferred paths
//! above, with tighter tolerances (it shades each triangle at the pixel centre, as forward
//! does, rather than each sample at its own point), and its shading-frequency view.

use super::*;

/// Mean and 99th percentile of the per-channel difference from naive forward. Measured: mean
/// 0.001 to 0.007, 99th percentile 0, largest 1 to 5 (lavapipe).
const VIS_MEAN: f64 = 0.05;
const VIS_P99: u8 = 1;
/// The largest per-channel difference (edges of MSAA pixels, and points rebuilt from the
/// triangle's plane rather than interpolated).
const VIS_MAX: u8 = 8;

#[test]
fn the_visibility_path_equals_naive_forward_at_msaa_1_and_4() {
    gpu_test(|gpu| {
        let stages = [
            ("courtyard", courtyard_stage()),
            ("glTF", gltf_stage()),
            ("city", city_stage()),
        ];
        for (name, stage) in stages {
            for msaa in [1, 4] {
                let default = EdgeThresholds::default();
                let (naive, _) = frame(gpu, &stage, RenderPath::NaivePrez, msaa, default, false);
                let (vis, _) = frame(gpu, &stage, RenderPath::Visibility, msaa, default, false);
                let what = format!("{name}, visibility, MSAA {msaa}");
                let d = pixel_differences(&naive, &vis, 3);
                let (mean, p99, largest) = stats(&d);
                eprintln!("{what}: mean {mean:.3}, 99th percentile {p99}, largest {largest}");
                assert!(
                    mean <= VIS_MEAN && p99 <= VIS_P99 && largest <= VIS_MAX,
                    "{what}: differs from naive forward by mean {mean:.3}, 99th percentile \
                     {p99}, largest {largest} (tolerances {VIS_MEAN}, {VIS_P99}, {VIS_MAX})"
                );
            }
        }
    });
}

/// Every pixel the TBDR path shades per sample sees more than one surface, so more than one
/// triangle: the visibility path's shading-frequency view marks it red, and more besides (the
/// edges between triangles of one surface).
#[test]
fn the_visibility_shading_frequency_view_marks_every_pixel_of_several_triangles() {
    gpu_test(|gpu| {
        let stage = courtyard_stage();
        let t = EdgeThresholds::default();
        let (_, record) = frame(gpu, &stage, RenderPath::Tbdr, 4, t, true);
        let record = record.expect("recorded");
        let rgba = shading_frequency_frame(gpu, &stage, RenderPath::Visibility);
        let red = |p: &[u8]| p[0] > 200 && p[1] < 120 && p[2] < 120;
        let (mut edges, mut red_edges, mut red_all) = (0, 0, 0);
        for (i, p) in rgba.chunks(4).enumerate() {
            let (x, y) = (i as u32 % record.width, i as u32 / record.width);
            red_all += u32::from(red(p));
            if record.is_edge(x, y) {
                edges += 1;
                red_edges += u32::from(red(p));
            }
        }
        eprintln!("{red_edges} of {edges} TBDR edge pixels red, {red_all} red in all");
        // Blended glass drawn over a few edges tints them.
        assert!(
            edges > 300 && red_edges * 100 >= edges * 98,
            "{red_edges} of {edges} TBDR edge pixels are red"
        );
        assert!(
            red_all > edges && red_all * 3 < rgba.len() as u32 / 4,
            "{red_all} pixels are red ({edges} TBDR edges)"
        );
    });
}
