//! Golden tests in the style of naga's `tests/in` → `tests/out`: every DSL program in
//! `tests/dsl-golden/*.rs` is compiled by `codegen` (no proc-macro), each distinct variant's
//! WGSL is an insta snapshot in `tests/dsl-golden/snapshots/`, and each variant's SPIR-V must
//! pass `spirv-val` for Vulkan 1.1 (which accepts SPIR-V up to 1.3). A file's `#[library]`
//! modules are merged into the modules that use them, and are also compiled on their own
//! (every function kept), with snapshots of their own.
//!
//! Review changes with `cargo insta review`, or re-approve with `INSTA_UPDATE=always`.

use std::path::{Path, PathBuf};
use std::process::Command;

fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/dsl-golden")
}

fn corpus() -> Vec<(String, String)> {
    let mut files: Vec<_> = std::fs::read_dir(corpus_dir())
        .expect("tests/dsl-golden exists")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "rs"))
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let stem = p
                .file_stem()
                .expect("file name")
                .to_string_lossy()
                .into_owned();
            (
                stem,
                std::fs::read_to_string(&p).expect("readable corpus file"),
            )
        })
        .collect()
}

fn compile(stem: &str, src: &str) -> codegen::Compiled {
    codegen::compile_source(src).unwrap_or_else(|e| {
        let at = e.span().start();
        panic!("{stem}.rs:{}:{}: {e}", at.line, at.column)
    })
}

/// Runs a spirv-tools binary; a missing tool is a test failure, never a skip.
fn spirv_tool(tool: &str, words: &[u32], args: &[&str], name: &str) -> String {
    let dir = std::env::temp_dir().join(format!("dsl-golden-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(format!("{name}.spv"));
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    std::fs::write(&path, bytes).expect("write SPIR-V");
    let out = Command::new(tool)
        .args(args)
        .arg(&path)
        .output()
        .unwrap_or_else(|e| {
            panic!("`{tool}` is required by the golden tests (Debian package `spirv-tools`): {e}")
        });
    assert!(
        out.status.success(),
        "{tool} rejected {name}:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("utf-8 output")
}

#[test]
fn golden_wgsl_snapshots_and_spirv_val() {
    let snapshots = corpus_dir().join("snapshots");
    let mut checked = 0;
    for (stem, src) in corpus() {
        let compiled = compile(&stem, &src);
        for v in &compiled.variants {
            let name = format!("{stem}@{}", v.names[0]);
            insta::with_settings!({
                snapshot_path => &snapshots,
                prepend_module_to_snapshot => false,
                omit_expression => true,
                description => format!("{stem}: keys {}", v.names.join(", ")),
            }, {
                insta::assert_snapshot!(format!("{name}.wgsl"), &v.wgsl);
            });
            // Every variant, the SampleMask built-in included (naga 30 writes it as a scalar;
            // the DSL's SPIR-V step makes it the array Vulkan requires).
            spirv_tool("spirv-val", &v.spirv, &["--target-env", "vulkan1.1"], &name);
            checked += 1;
        }
    }
    assert!(
        checked >= 30,
        "expected the whole corpus, checked {checked} variants"
    );
}

#[test]
fn golden_libraries_on_their_own() {
    let snapshots = corpus_dir().join("snapshots");
    let mut checked = 0;
    for (stem, src) in corpus() {
        let file = syn::parse_file(&src).expect("corpus file parses");
        let libraries = codegen::library_modules(&file);
        for (args, item) in &libraries {
            let lib = item.ident.to_string();
            let compiled = codegen::compile_library_with_libraries(args.clone(), item, &libraries)
                .unwrap_or_else(|e| {
                    let at = e.span().start();
                    panic!("{stem}.rs:{}:{}: {e}", at.line, at.column)
                });
            for v in &compiled.variants {
                let name = format!("{stem}@{lib}@{}", v.names[0]);
                insta::with_settings!({
                    snapshot_path => &snapshots,
                    prepend_module_to_snapshot => false,
                    omit_expression => true,
                    description => format!("library {lib} of {stem}: keys {}", v.names.join(", ")),
                }, {
                    insta::assert_snapshot!(format!("{name}.wgsl"), &v.wgsl);
                });
                // Without entry points naga declares the `Linkage` capability, which Vulkan
                // rejects; the universal environment checks everything else.
                spirv_tool("spirv-val", &v.spirv, &["--target-env", "spv1.3"], &name);
                checked += 1;
            }
        }
    }
    assert!(
        checked >= 2,
        "expected the corpus libraries, checked {checked} variants"
    );
}

#[test]
fn golden_spirv_disassembly() {
    let src = std::fs::read_to_string(corpus_dir().join("compute_basic.rs")).expect("corpus file");
    let compiled = compile("compute_basic", &src);
    let v = &compiled.variants[0];
    let dis = spirv_tool("spirv-dis", &v.spirv, &["--raw-id"], "compute_basic_dis");
    insta::with_settings!({
        snapshot_path => corpus_dir().join("snapshots"),
        prepend_module_to_snapshot => false,
        omit_expression => true,
    }, {
        insta::assert_snapshot!("compute_basic@t8.spvasm", dis);
    });
}

/// The SampleMask rewrite as reviewable text: the input and output variables are
/// `array<uint, 1>` and every load and store goes through element 0.
#[test]
fn golden_sample_mask_disassembly() {
    let src = std::fs::read_to_string(corpus_dir().join("sample_mask.rs")).expect("corpus file");
    let compiled = compile("sample_mask", &src);
    let v = &compiled.variants[0];
    let dis = spirv_tool("spirv-dis", &v.spirv, &["--raw-id"], "sample_mask_dis");
    assert_eq!(
        dis.matches("OpAccessChain").count(),
        2,
        "one load of the input and one store of the output, each through element 0:\n{dis}"
    );
    insta::with_settings!({
        snapshot_path => corpus_dir().join("snapshots"),
        prepend_module_to_snapshot => false,
        omit_expression => true,
    }, {
        insta::assert_snapshot!("sample_mask@default.spvasm", dis);
    });
}

#[test]
fn the_three_axis_module_has_24_validated_variants() {
    let src = std::fs::read_to_string(corpus_dir().join("tile_cull.rs")).expect("corpus file");
    assert!(src.lines().count() >= 150);
    let compiled = compile("tile_cull", &src);
    assert_eq!(compiled.keys.len(), 24);
    assert!(compiled.key_variant.iter().all(Option::is_some));
    let names: Vec<&str> = compiled
        .variants
        .iter()
        .flat_map(|v| v.names.iter().map(String::as_str))
        .collect();
    assert_eq!(names.len(), 24);
    assert!(names.contains(&"t16_msaa4_scalar"));
    for v in &compiled.variants {
        let scalar = v.names[0].ends_with("_scalar");
        assert_eq!(v.reflection.features.subgroup, scalar, "{}", v.names[0]);
        assert_eq!(v.spirv_version, if scalar { (1, 3) } else { (1, 0) });
    }
}

#[test]
fn generation_is_deterministic() {
    for (stem, src) in corpus() {
        let a = compile(&stem, &src);
        let b = compile(&stem, &src);
        for (x, y) in a.variants.iter().zip(&b.variants) {
            assert_eq!(x.wgsl, y.wgsl, "{stem}");
            assert_eq!(x.spirv, y.spirv, "{stem}");
        }
    }
}
