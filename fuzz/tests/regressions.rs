//! Every committed fuzz input replays as an ordinary test: `regressions/<target>/` holds each
//! crash a fuzzer found (named after what it found), fixed since; the glTF seeds run too.

use std::path::Path;

fn replay(target: &str, run: fn(&[u8])) -> usize {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("regressions")
        .join(target);
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
    for &(target, run) in fuzz::TARGETS {
        replay(target, run);
    }
}

#[test]
fn the_gltf_seeds_load_or_fail_cleanly_and_the_valid_ones_load() {
    let seeds = fuzz::gltf_seeds::seeds();
    assert!(
        seeds.len() >= 8,
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
