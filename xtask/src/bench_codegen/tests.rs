//! Tests of `bench-codegen`: percentiles, the one-line kernel edit (and that the DSL accepts it),
//! the scratch workspace's manifest, and that the rebuild measurement edits only its copy: the
//! checkout's file keeps its bytes through every build, a failed build and a panic included.

use std::path::{Path, PathBuf};
use std::time::Duration;

use super::figures::{Stats, percentile};
use super::rebuild::{EDIT_MARKER, EDITED_FILE, check_dsl_accepts, edited_source, time_rebuilds};
use super::scratch::{Scratch, scratch_manifest};
use super::shaders_gen_libraries;

#[test]
fn percentiles() {
    assert!(percentile(&[], 50.0).is_nan());
    assert_eq!(percentile(&[3.0], 90.0), 3.0);
    assert_eq!(percentile(&[1.0, 2.0, 3.0], 50.0), 2.0);
    assert_eq!(percentile(&[1.0, 2.0, 3.0, 4.0], 50.0), 2.5);
    let ten: Vec<f64> = (1..=11).map(f64::from).collect();
    assert_eq!(percentile(&ten, 90.0), 10.0);
    assert_eq!(percentile(&ten, 100.0), 11.0);
    assert_eq!(percentile(&ten, 0.0), 1.0);
    let s = Stats::of(&[5.0, 1.0, 4.0, 2.0, 3.0]);
    assert_eq!((s.samples, s.median, s.max), (5, 3.0, 5.0));
    assert!((s.p90 - 4.6).abs() < 1e-12);
}

#[test]
fn the_edit_adds_one_line_to_the_compute_body() {
    let src = "mod m {\n    fn helper() {\n        x();\n    }\n    #[compute(workgroup_size(8, 1, 1))]\n    pub fn cull(\n        #[builtin(local_invocation_index)] lid: u32,\n    ) {\n        if lid == 0u32 {}\n    }\n}\n";
    let a = edited_source(src, 0).unwrap();
    let b = edited_source(src, 1).unwrap();
    assert_ne!(a, b);
    let lines: Vec<&str> = a.lines().collect();
    assert_eq!(lines.len(), src.lines().count() + 1);
    assert_eq!(lines[7], "    ) {");
    assert_eq!(lines[8], "        let bench_codegen_edit = 0u32;");
    let without: Vec<&str> = lines
        .iter()
        .copied()
        .filter(|l| !l.contains(EDIT_MARKER))
        .collect();
    assert_eq!(without, src.lines().collect::<Vec<_>>());
    assert!(edited_source("fn f() {}\n", 0).is_err());
}

/// The real kernel, edited in memory only: the DSL accepts both edits.
#[test]
fn the_dsl_accepts_the_edited_kernel() {
    let src =
        std::fs::read_to_string(crate::workspace::workspace_root().join(EDITED_FILE)).unwrap();
    assert!(!src.contains(EDIT_MARKER));
    let libraries = shaders_gen_libraries(&crate::workspace::workspace_root()).unwrap();
    for value in [0, 1] {
        check_dsl_accepts(&edited_source(&src, value).unwrap(), &libraries).unwrap();
    }
}

const KERNEL: &str = "#[shader]\nmod m {\n    #[compute(workgroup_size(8, 1, 1))]\n    pub fn cull() {\n        x();\n    }\n}\n";

/// A small workspace like the checkout, in a temporary folder: the root manifest and lock, and
/// `shaders_gen` with the kernel the benchmark edits.
fn fake_checkout(name: &str) -> PathBuf {
    let root =
        std::env::temp_dir().join(format!("xtask-bench-codegen-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    let write = |path: &str, text: &str| {
        let path = root.join(path);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    };
    write(
        "Cargo.toml",
        "[workspace]\nmembers = [\"shaders_gen\", \"codegen\"]\n\n[workspace.dependencies]\ncodegen = { path = \"codegen\" }\n",
    );
    write("Cargo.lock", "version = 4\n");
    write(
        "shaders_gen/Cargo.toml",
        "[package]\nname = \"shaders_gen\"\n",
    );
    write("shaders_gen/src/lib.rs", "pub mod culling;\n");
    write(EDITED_FILE, KERNEL);
    root
}

fn checkout_file(root: &Path) -> String {
    std::fs::read_to_string(root.join(EDITED_FILE)).unwrap()
}

/// Every build sees the checkout's kernel unchanged and the copy holding the expected text: the
/// edits (two alternating), the original again, then the touches.
#[test]
fn the_rebuilds_edit_a_copy_and_never_the_checkout() {
    let root = fake_checkout("copy");
    let scratch = root.join("target/bench/codegen-workspace");
    let mut seen = vec![];
    let times = time_rebuilds(&root, &scratch, 3, |dir, expect_rebuild| {
        assert_eq!(dir, scratch, "the build runs in the scratch workspace");
        assert_eq!(checkout_file(&root), KERNEL, "the checkout was edited");
        let copy = std::fs::read_to_string(dir.join(EDITED_FILE)).unwrap();
        seen.push((expect_rebuild, copy));
        Ok(Duration::from_millis(10))
    })
    .unwrap();
    let (edit0, edit1) = (
        edited_source(KERNEL, 0).unwrap(),
        edited_source(KERNEL, 1).unwrap(),
    );
    let expected = [
        (false, KERNEL),
        (true, &edit0),
        (true, &edit1),
        (true, &edit0),
        (true, KERNEL),
        (true, KERNEL),
        (true, KERNEL),
        (true, KERNEL),
    ];
    let seen: Vec<(bool, &str)> = seen.iter().map(|(e, t)| (*e, t.as_str())).collect();
    assert_eq!(seen, expected.map(|(e, t)| (e, t as &str)));
    assert_eq!((times.edit_s.len(), times.touch_s.len()), (3, 3));
    assert_eq!(checkout_file(&root), KERNEL);
    assert!(!scratch.exists(), "the scratch workspace is removed");
    std::fs::remove_dir_all(&root).unwrap();
}

/// A build that fails, and one that panics, mid-way (as a Ctrl-C would stop it): the checkout's
/// kernel still has its bytes, with nothing to restore.
#[test]
fn a_failed_or_interrupted_rebuild_leaves_the_checkout_as_it_was() {
    let root = fake_checkout("failed");
    let scratch = root.join("target/bench/codegen-workspace");
    let mut builds = 0;
    let failed = time_rebuilds(&root, &scratch, 3, |_, _| {
        builds += 1;
        if builds == 3 {
            anyhow::bail!("the build failed");
        }
        Ok(Duration::ZERO)
    });
    assert!(failed.is_err());
    assert_eq!(checkout_file(&root), KERNEL);
    let panicked = std::panic::catch_unwind(|| {
        time_rebuilds(&root, &scratch, 3, |dir, expect_rebuild| {
            if expect_rebuild {
                // Killed while the copy holds the edit.
                assert!(
                    std::fs::read_to_string(dir.join(EDITED_FILE))
                        .unwrap()
                        .contains(EDIT_MARKER)
                );
                panic!("interrupted");
            }
            Ok(Duration::ZERO)
        })
    });
    assert!(panicked.is_err());
    assert_eq!(checkout_file(&root), KERNEL);
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn only_files_of_the_copied_crate_have_a_copy() {
    let root = fake_checkout("copy-of");
    let scratch = Scratch::create(&root, &root.join("target/scratch")).unwrap();
    let copy = scratch.copy_of(EDITED_FILE).unwrap();
    assert!(copy.starts_with(scratch.dir()) && copy.is_file());
    assert!(scratch.copy_of("renderer/src/lib.rs").is_err());
    drop(scratch);
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn the_scratch_manifest_narrows_the_members_and_points_back_at_the_checkout() {
    let manifest = "[workspace]\nresolver = \"3\"\nmembers = [\n    \"shaders_gen\",\n    \"renderer\",\n]\ndefault-members = [\"renderer\"]\n\n[workspace.dependencies]\nglam = { version = \"0.34\" }\ncodegen = { path = \"codegen\", default-features = false }\nshaders_gen = { path = \"shaders_gen\" }\n\n[profile.dev.package.codegen]\nopt-level = 3\n";
    let out = scratch_manifest(manifest, Path::new("/checkout")).unwrap();
    assert_eq!(
        out,
        "[workspace]\nresolver = \"3\"\nmembers = [\"shaders_gen\"]\n\n[workspace.dependencies]\nglam = { version = \"0.34\" }\ncodegen = { path = \"/checkout/codegen\", default-features = false }\nshaders_gen = { path = \"shaders_gen\" }\n\n[profile.dev.package.codegen]\nopt-level = 3\n"
    );
    assert!(scratch_manifest("[package]\nname = \"x\"\n", Path::new("/c")).is_err());
}

/// This checkout's scratch workspace is one cargo resolves: its package is the copy, and its
/// `codegen` and `shader-dsl` are the checkout's.
#[test]
fn this_checkouts_scratch_workspace_resolves_in_cargo() {
    let root = crate::workspace::workspace_root();
    let dir = root.join(format!(
        "target/bench/codegen-workspace-test-{}",
        std::process::id()
    ));
    let scratch = Scratch::create(&root, &dir).unwrap();
    let output = std::process::Command::new(env!("CARGO"))
        .current_dir(scratch.dir())
        .args(["tree", "--offline", "-p", "shaders_gen", "-e", "normal"])
        .args(["--depth", "1", "--prefix", "none", "--color", "never"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "cargo tree failed:\n{stderr}");
    let tree = String::from_utf8_lossy(&output.stdout);
    let package = |name: &str, dir: PathBuf| format!("{name} v0.1.0 ({})", dir.display());
    for expected in [
        package("shaders_gen", dir.join("shaders_gen")),
        package("codegen", root.join("codegen")),
        package("shader-dsl", root.join("shader-dsl")).replace(" (", " (proc-macro) ("),
    ] {
        assert!(tree.contains(&expected), "no `{expected}` in:\n{tree}");
    }
    drop(scratch);
    assert!(!dir.exists());
}
