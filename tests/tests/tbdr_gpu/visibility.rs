//! The visibility path against naive forward: the same scenes, cameras and tolerances as the
//! deferred paths above.

use super::*;

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
                    mean <= MEAN_TOLERANCE && p99 <= P99_TOLERANCE,
                    "{what}: differs from naive forward by mean {mean:.3}, 99th percentile \
                     {p99} (tolerances {MEAN_TOLERANCE}, {P99_TOLERANCE})"
                );
            }
        }
    });
}
