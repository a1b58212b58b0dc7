//! `cargo xtask test`: the README's test command, and what CI runs.
//!
//! It provisions the system packages the GPU tests need, then runs formatting, clippy (over the
//! workspace, over the renderer without its default features, as an engine may build it, and
//! over the renderer and the web demo for wasm32), the architecture invariants,
//! `cargo xtask shaders --check` (every shaders_gen variant written and passed by `spirv-val`),
//! the web demo's build (which the browser frame test loads), every workspace test (doc tests
//! included) and the tests of the engine example outside the workspace (`examples/engine`),
//! stopping at the first failing step. It ends with a one-line `N passed, N failed` summary.

use std::io::{BufRead as _, BufReader};
use std::process::{Command, Stdio};
use std::time::Instant;

use anyhow::{Context as _, Result, bail};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Extra arguments passed to `cargo test` (for example a test name filter after `--`).
    #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
    cargo_test_args: Vec<String>,
}

#[expect(
    clippy::print_stdout,
    reason = "progress report of a command-line tool"
)]
pub fn run(args: &Args) -> Result<()> {
    let started = Instant::now();
    step("system packages", crate::system::ensure_test_requirements)?;
    step("cargo fmt --check", || {
        cargo(&["fmt", "--all", "--check"])?;
        rustfmt_check_every_file()
    })?;
    step("cargo clippy", || {
        cargo(&[
            "clippy",
            "--workspace",
            "--all-targets",
            "--",
            "-D",
            "warnings",
        ])
    })?;
    // The renderer as an engine without glTF, PNG or JSON builds it: every public item
    // documented, nothing unused once the internal modules are `pub(crate)`.
    step("cargo clippy -p renderer --no-default-features", || {
        cargo(&[
            "clippy",
            "-p",
            "renderer",
            "--no-default-features",
            "--",
            "-D",
            "warnings",
        ])
    })?;
    // The renderer and the web demo for the browser (wasm32, wgpu's WebGPU backend): nothing
    // native-only creeps into them unnoticed.
    step(
        "cargo clippy -p renderer -p web-demo --target wasm32-unknown-unknown",
        || {
            crate::system::ensure_wasm_target()?;
            cargo(&[
                "clippy",
                "-p",
                "renderer",
                "-p",
                "web-demo",
                "--target",
                crate::system::WASM_TARGET,
                "--",
                "-D",
                "warnings",
            ])
        },
    )?;
    step("architecture invariants", crate::invariants::run)?;
    step("cargo xtask shaders --check", || {
        crate::shaders::run(&crate::shaders::Args::check_all())
    })?;
    // The web demo's module, which the browser frame test loads in headless Chromium.
    // The dev profile: the tests' host build of the DSL compiler serves it (a release build
    // compiles that again, and every dependency optimised: minutes more from scratch).
    step("cargo xtask web --build-only --dev", || {
        crate::web::build(crate::web::Profile::Dev).map(|_| ())
    })?;
    let mut counts = step("cargo test", || cargo_test(&args.cargo_test_args))?;
    let example = step(
        "engine example (crates outside the workspace)",
        engine_example_test,
    )?;
    counts.passed += example.passed;
    counts.failed += example.failed;
    println!(
        "xtask test: all steps done in {:.1} s",
        started.elapsed().as_secs_f64()
    );
    println!("{} passed, {} failed", counts.passed, counts.failed);
    if counts.failed > 0 {
        bail!("{} test(s) failed", counts.failed);
    }
    Ok(())
}

#[expect(
    clippy::print_stdout,
    reason = "progress report of a command-line tool"
)]
fn step<T>(name: &str, f: impl FnOnce() -> Result<T>) -> Result<T> {
    println!("xtask test: {name} ...");
    let started = Instant::now();
    let result = f();
    let secs = started.elapsed().as_secs_f64();
    match &result {
        Ok(_) => println!("xtask test: {name} ok ({secs:.1} s)"),
        Err(e) => {
            println!("xtask test: {name} FAILED ({secs:.1} s): {e:#}");
            println!("0 passed, 1 failed");
        }
    }
    result
}

/// `cargo fmt` formats the files it reaches through `mod` items, and rustfmt does not expand
/// macros: the renderer declares its internal modules through one (`internal_modules!`), so
/// `cargo fmt --check` never saw them. The engine example is a workspace of its own. So every
/// `.rs` file of every crate here and in `examples/engine` is checked by name too, but the
/// compile-fail cases (`tests/ui`), whose expected messages name their lines.
fn rustfmt_check_every_file() -> Result<()> {
    let root = crate::workspace::workspace_root();
    let files = formatted_files(&root)?;
    let status = Command::new("rustfmt")
        .args(["--check", "--edition", "2024"])
        .args(&files)
        .current_dir(&root)
        .status()
        .context("running rustfmt")?;
    if !status.success() {
        bail!(
            "rustfmt --check found unformatted files among {} (run rustfmt --edition 2024 on them)",
            files.len()
        );
    }
    Ok(())
}

/// The `.rs` files rustfmt must find formatted: those of every crate folder (`src`, `tests`,
/// `benches`, `examples`, `fuzz_targets`) of the workspace's members and the engine example's,
/// without `tests/ui`.
fn formatted_files(root: &std::path::Path) -> Result<Vec<std::path::PathBuf>> {
    let folders = crate::invariants::lengths::SOURCE_FOLDERS;
    let mut files = crate::invariants::crate_source_files(root, folders)?;
    files.extend(crate::invariants::crate_source_files(
        &root.join("examples/engine"),
        folders,
    )?);
    // The compile-fail cases' `.stderr` files name their lines: leave them as written.
    files.retain(|f| !f.ancestors().any(|folder| folder.ends_with("tests/ui")));
    files.sort();
    Ok(files)
}

fn cargo(args: &[&str]) -> Result<()> {
    let status = Command::new(env!("CARGO"))
        .args(args)
        .current_dir(crate::workspace::workspace_root())
        .status()
        .with_context(|| format!("running cargo {}", args.join(" ")))?;
    if !status.success() {
        bail!("cargo {} failed with {status}", args.join(" "));
    }
    Ok(())
}

/// Totals over every `test result:` line that libtest printed.
#[derive(Debug, Default, PartialEq, Eq)]
pub struct Counts {
    pub passed: u64,
    pub failed: u64,
}

impl Counts {
    /// Adds the counts of one libtest summary line, such as
    /// `test result: ok. 3 passed; 0 failed; 0 ignored; 0 measured; 0 filtered out; ...`.
    pub fn add_line(&mut self, line: &str) {
        let Some(rest) = line.trim().strip_prefix("test result: ") else {
            return;
        };
        for part in rest.split(';') {
            let mut words = part.split_whitespace().rev();
            let (Some(label), Some(number)) = (words.next(), words.next()) else {
                continue;
            };
            let Ok(n) = number.parse::<u64>() else {
                continue;
            };
            match label {
                "passed" => self.passed += n,
                "failed" => self.failed += n,
                _ => {}
            }
        }
    }
}

/// Runs the workspace tests, echoing their output while counting results. A test binary that
/// fails to build or crashes counts as one failure even if it printed no summary.
fn cargo_test(extra: &[String]) -> Result<Counts> {
    let mut command = Command::new(env!("CARGO"));
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        // Mesa's Vulkan drivers complain on every device creation without one (CI has none).
        command.env("XDG_RUNTIME_DIR", private_runtime_dir()?);
    }
    command
        .args(["test", "--workspace", "--no-fail-fast"])
        .args(extra)
        .current_dir(crate::workspace::workspace_root());
    run_counted(command)
}

/// The engine example's tests (`examples/engine`: a shader library crate, a crate using it and
/// the renderer's libraries, and an app embedding the renderer with a pass of its own, outside
/// the workspace), built in the workspace's target directory.
fn engine_example_test() -> Result<Counts> {
    let root = crate::workspace::workspace_root();
    let mut command = Command::new(env!("CARGO"));
    command
        .args(["test", "--locked", "--manifest-path"])
        .arg(root.join("examples/engine/Cargo.toml"))
        .env("CARGO_TARGET_DIR", root.join("target"))
        .current_dir(&root);
    run_counted(command)
}

/// Runs a `cargo test` command, echoing its output while counting results.
#[expect(clippy::print_stdout, reason = "echoes the test output")]
fn run_counted(mut command: Command) -> Result<Counts> {
    let mut child = command
        .stdout(Stdio::piped())
        .spawn()
        .context("running cargo test")?;
    let stdout = child.stdout.take().context("capturing cargo test output")?;
    let mut counts = Counts::default();
    for line in BufReader::new(stdout).lines() {
        let line = line.context("reading cargo test output")?;
        println!("{line}");
        counts.add_line(&line);
    }
    let status = child.wait().context("waiting for cargo test")?;
    if !status.success() && counts.failed == 0 {
        counts.failed = 1;
    }
    Ok(counts)
}

/// A runtime directory only this user can use (what `XDG_RUNTIME_DIR` must be).
fn private_runtime_dir() -> Result<std::path::PathBuf> {
    use std::os::unix::fs::PermissionsExt as _;
    let dir = crate::workspace::workspace_root().join("target/xdg-runtime");
    std::fs::create_dir_all(&dir).context("creating target/xdg-runtime")?;
    std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o700))
        .context("restricting target/xdg-runtime")?;
    Ok(dir)
}

#[cfg(test)]
mod tests {
    use super::Counts;

    /// The files the format check names include those `cargo fmt` does not reach (the renderer's
    /// macro-declared modules, the engine example) and leave out the compile-fail cases.
    #[test]
    fn the_format_check_names_the_files_cargo_fmt_cannot_reach() {
        let root = crate::workspace::workspace_root();
        let files = super::formatted_files(&root).expect("listing");
        for reached in [
            "renderer/src/passes/forward/overlay.rs",
            "renderer/src/culling/hierarchy.rs",
            "examples/engine/app/src/lib.rs",
            "xtask/src/test.rs",
        ] {
            assert!(
                files.contains(&root.join(reached)),
                "{reached} is not checked"
            );
        }
        let ui = root.join("shader-dsl/tests/ui");
        assert!(ui.is_dir());
        assert!(
            !files.iter().any(|f| f.starts_with(&ui)),
            "a compile-fail case is checked"
        );
    }

    #[test]
    fn counts_sum_libtest_summaries() {
        let mut c = Counts::default();
        c.add_line("test result: ok. 3 passed; 0 failed; 0 ignored; 0 measured; 0 filtered out; finished in 0.01s");
        c.add_line(
            "test result: FAILED. 5 passed; 2 failed; 0 ignored; 0 measured; 1 filtered out",
        );
        c.add_line("running 7 tests");
        c.add_line("test foo::bar ... ok");
        assert_eq!(
            c,
            Counts {
                passed: 8,
                failed: 2
            }
        );
    }
}
