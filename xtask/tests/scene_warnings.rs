//! `cargo xtask render` prints each warning of the scene it opens once, on stderr, as
//! `warning: <path>: <warning>`: the binary itself is run on a committed sample model whose
//! point and line meshes are skipped (lavapipe in CI renders it).

use std::path::Path;
use std::process::Command;

#[test]
fn render_prints_each_scene_warning_once() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/scenes/MeshPrimitiveModes/MeshPrimitiveModes.gltf");
    let scene_arg = scene.to_string_lossy().into_owned();
    let out = std::env::temp_dir().join(format!("xtask-scene-warnings-{}.png", std::process::id()));
    let result = Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args([
            "render", "--scene", &scene_arg, "--size", "32x18", "--lights", "1",
        ])
        .arg("--out")
        .arg(&out)
        .output()
        .expect("the xtask binary runs");
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(result.status.success(), "render failed:\n{stderr}");
    std::fs::remove_file(&out).ok();
    for mode in ["POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"] {
        let line = format!(
            "warning: {scene_arg}: mesh `mesh with {mode}` primitive 0 is {mode}, which this \
             renderer does not draw; it is skipped"
        );
        assert_eq!(
            stderr.lines().filter(|l| *l == line).count(),
            1,
            "want {line:?} once in:\n{stderr}"
        );
    }
    assert_eq!(
        stderr
            .lines()
            .filter(|l| l.starts_with("warning: "))
            .count(),
        4,
        "no other warning:\n{stderr}"
    );
}
