//! Every committed fuzz input replays as an ordinary test: `regressions/<target>/` holds each
//! crash a fuzzer found (named after what it found), fixed since; the glTF seeds run too.

use std::path::{Path, PathBuf};

fn regressions_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("regressions")
}

/// Replays `regressions/<target>/*`. A target without a folder has no findings yet: git does
/// not keep empty folders, so a missing folder is the same as an empty one.
fn replay(target: &str, run: fn(&[u8])) -> usize {
    let dir = regressions_dir().join(target);
    if !dir.exists() {
        return 0;
    }
    let mut inputs: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.is_file())
        .collect();
    inputs.sort();
    for input in &inputs {
        let bytes = std::fs::read(input).expect("read regression input");
        eprintln!("{target}: {}", input.display());
        run(&bytes);
    }
    inputs.len()
}

#[test]
fn every_target_replays_its_regressions() {
    let replayed: usize = fuzz::TARGETS
        .iter()
        .map(|&(target, run)| replay(target, run))
        .sum();
    assert!(
        replayed >= 3,
        "the committed gltf_load findings are missing"
    );
}

/// A folder named after no target would never be replayed: it is an error, not a silent skip.
#[test]
fn every_regression_folder_belongs_to_a_target() {
    for entry in std::fs::read_dir(regressions_dir()).expect("regressions folder") {
        let path = entry.expect("directory entry").path();
        if path.is_dir() {
            let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
            assert!(
                fuzz::TARGETS.iter().any(|&(target, _)| target == name),
                "{} is not a fuzz target's folder; targets: {:?}",
                path.display(),
                fuzz::TARGETS.iter().map(|t| t.0).collect::<Vec<_>>()
            );
        }
    }
}

#[test]
fn the_gltf_seeds_load_or_fail_cleanly_and_the_valid_ones_load() {
    let seeds = fuzz::gltf_seeds::seeds();
    assert!(
        seeds.len() >= 9,
        "the shared LightsPunctualLamp seed is missing"
    );
    for (name, bytes) in &seeds {
        fuzz::gltf_load::run(bytes);
        let loaded = renderer::scene::Scene::from_slice(bytes);
        let should_load = ["triangle", "lights-punctual-lamp"]
            .iter()
            .any(|p| name.starts_with(p));
        assert_eq!(loaded.is_ok(), should_load, "{name}: {:?}", loaded.err());
    }
}
