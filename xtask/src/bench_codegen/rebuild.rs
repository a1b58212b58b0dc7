//! `bench-codegen`'s incremental rebuild: `cargo build -p shaders_gen` after a one-line edit of a
//! compute kernel, and after a `touch`, both made in a copy of the crate ([`Scratch`]): the
//! checkout is only read, so no run, crash or Ctrl-C can leave it modified.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant, SystemTime};

use anyhow::{Context as _, Result, anyhow, bail, ensure};

use super::scratch::{SCRATCH_DIR, Scratch};
use crate::shaders::DslModule;

/// The kernel edited (in the copy) for the incremental rebuild, relative to the workspace root.
pub(super) const EDITED_FILE: &str = "shaders_gen/src/culling/tiled.rs";
/// Name of the variable the edit declares.
pub(super) const EDIT_MARKER: &str = "bench_codegen_edit";

/// Times the rebuilds of the copy of `shaders_gen` in a scratch workspace under `root`, after
/// checking that the DSL (with `shaders_gen`'s `libraries`) accepts both edits.
pub(super) fn measure_rebuild(
    root: &Path,
    release: bool,
    rebuilds: u32,
    libraries: &[DslModule],
) -> Result<Times> {
    let original = std::fs::read_to_string(root.join(EDITED_FILE))
        .with_context(|| format!("reading {EDITED_FILE}"))?;
    for value in [0, 1] {
        check_dsl_accepts(&edited_source(&original, value)?, libraries)
            .context("the DSL rejects the benchmark's one-line kernel edit")?;
    }
    let target_dir = target_dir(root);
    time_rebuilds(
        root,
        &root.join(SCRATCH_DIR),
        rebuilds,
        |dir, expect_rebuild| cargo_build(dir, &target_dir, release, expect_rebuild),
    )
}

/// The seconds [`time_rebuilds`] measured.
#[derive(Debug)]
pub(super) struct Times {
    pub warmup_s: f64,
    pub edit_s: Vec<f64>,
    pub touch_s: Vec<f64>,
}

/// Copies `shaders_gen` of `root` into a scratch workspace at `scratch_dir` and times `build` (a
/// build of the workspace at the folder it is given; `true`: it must recompile shaders_gen): a
/// warm-up, `rebuilds` builds after an edit of the copy of [`EDITED_FILE`], then `rebuilds` after
/// a touch of the copy. Reads `root` and writes only under `scratch_dir`, which it removes.
pub(super) fn time_rebuilds(
    root: &Path,
    scratch_dir: &Path,
    rebuilds: u32,
    mut build: impl FnMut(&Path, bool) -> Result<Duration>,
) -> Result<Times> {
    let original = std::fs::read_to_string(root.join(EDITED_FILE))
        .with_context(|| format!("reading {EDITED_FILE}"))?;
    let edits = [edited_source(&original, 0)?, edited_source(&original, 1)?];
    let scratch = Scratch::create(root, scratch_dir)?;
    let path = scratch.copy_of(EDITED_FILE)?;
    eprintln!(
        "bench-codegen: warm-up `cargo build -p shaders_gen` (untimed) in the copy {}",
        scratch.dir().display()
    );
    let warmup = build(scratch.dir(), false)?;

    let mut edit_s = Vec::new();
    for i in 0..rebuilds as usize {
        write(&path, &edits[i % 2])?;
        let t = build(scratch.dir(), true)?;
        eprintln!(
            "bench-codegen: rebuild {}/{rebuilds} after the edit: {:.2} s",
            i + 1,
            t.as_secs_f64()
        );
        edit_s.push(t.as_secs_f64());
    }

    // Back to the original text, built untimed, before the touches are timed.
    write(&path, &original)?;
    build(scratch.dir(), true)?;
    let mut touch_s = Vec::new();
    for i in 0..rebuilds {
        touch(&path)?;
        let t = build(scratch.dir(), true)?;
        eprintln!(
            "bench-codegen: rebuild {}/{rebuilds} after a touch: {:.2} s",
            i + 1,
            t.as_secs_f64()
        );
        touch_s.push(t.as_secs_f64());
    }
    Ok(Times {
        warmup_s: warmup.as_secs_f64(),
        edit_s,
        touch_s,
    })
}

/// The build folder: `CARGO_TARGET_DIR` when set (cargo reads it from the inherited
/// environment), else the checkout's `target`, so the copy reuses the checkout's built
/// dependencies; the copy is a package of its own there, so the checkout's artifacts stay valid.
fn target_dir(root: &Path) -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| root.join("target"), PathBuf::from)
}

fn write(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))
}

/// `source` with one statement added at the top of the body of its first `#[compute]` function:
/// `let bench_codegen_edit = <value>u32;`. Different values give different macro input tokens.
pub(super) fn edited_source(source: &str, value: u32) -> Result<String> {
    let lines: Vec<&str> = source.split_inclusive('\n').collect();
    let compute = lines
        .iter()
        .position(|l| l.trim_start().starts_with("#[compute"))
        .context("no `#[compute]` function to edit")?;
    let open = (compute..lines.len())
        .find(|&i| lines[i].trim_end().ends_with('{') && lines[i].ends_with('\n'))
        .context("no body after `#[compute]`")?;
    let indent: String = lines
        .get(open + 1)
        .map(|l| l.chars().take_while(|c| *c == ' ' || *c == '\t').collect())
        .unwrap_or_default();
    let mut out = String::with_capacity(source.len() + 64);
    for (i, line) in lines.iter().enumerate() {
        out.push_str(line);
        if i == open {
            writeln!(out, "{indent}let {EDIT_MARKER} = {value}u32;")?;
        }
    }
    Ok(out)
}

/// Compiles every `#[shader] mod` of `source` in-process, with `shaders_gen`'s libraries;
/// fails on any error.
pub(super) fn check_dsl_accepts(source: &str, libraries: &[DslModule]) -> Result<()> {
    let file = syn::parse_file(source)?;
    let modules = codegen::shader_modules(&file);
    ensure!(!modules.is_empty(), "no `#[shader] mod` found");
    for (args, item) in modules {
        codegen::compile_with_libraries(args, &item, libraries)
            .map_err(|e| anyhow!("module `{}`: {e}", item.ident))?;
    }
    Ok(())
}

fn touch(path: &Path) -> Result<()> {
    std::fs::File::options()
        .write(true)
        .open(path)
        .and_then(|f| f.set_modified(SystemTime::now()))
        .with_context(|| format!("touching {}", path.display()))
}

/// Times `cargo build -p shaders_gen` in the workspace at `dir`, with the caller's environment
/// (incremental in the dev profile unless `CARGO_INCREMENTAL` says otherwise), into
/// `target_dir`. With `expect_rebuild`, fails when cargo did not recompile shaders_gen (the
/// measurement would be of a no-op).
fn cargo_build(
    dir: &Path,
    target_dir: &Path,
    release: bool,
    expect_rebuild: bool,
) -> Result<Duration> {
    let mut command = Command::new(env!("CARGO"));
    command
        .current_dir(dir)
        .args([
            "build",
            "-p",
            "shaders_gen",
            "--color",
            "never",
            "--target-dir",
        ])
        .arg(target_dir);
    if release {
        command.arg("--release");
    } else if std::env::var_os("CARGO_INCREMENTAL").is_none() {
        // The workspace's dev profile (copied into the scratch workspace) turns incremental
        // compilation off for CI's cold builds; a user's own crate has it on, as cargo's
        // default dev profile does, and that is the rebuild this measures.
        command.env("CARGO_INCREMENTAL", "1");
    }
    let start = Instant::now();
    let output = command.output().context("running cargo build")?;
    let elapsed = start.elapsed();
    let stderr = String::from_utf8_lossy(&output.stderr);
    if !output.status.success() {
        bail!("`cargo build -p shaders_gen` failed:\n{stderr}");
    }
    if expect_rebuild && !stderr.contains("Compiling shaders_gen") {
        bail!("`cargo build -p shaders_gen` did not recompile shaders_gen:\n{stderr}");
    }
    Ok(elapsed)
}
