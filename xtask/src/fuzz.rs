//! `cargo xtask fuzz TARGET --minutes M`: runs one coverage-guided fuzz target of the `fuzz`
//! crate with cargo-fuzz and libFuzzer, and summarises the run.
//!
//! Everything comes from the project's files: cargo-fuzz is installed at the pinned version when
//! missing, `RUSTC_BOOTSTRAP=1` lets the stable toolchain take the sanitizer flags cargo-fuzz
//! passes, and the corpus starts from the target's seeds and committed regressions. Limits
//! follow the project's goal: an input running over 1 s is a hang, any allocation over 2 GiB
//! (the binaries' allocator, `fuzz::alloc_limit`) or resident memory over 2 GiB is a failure. A failing input is left in
//! `target/fuzz/artifacts/TARGET/`; once fixed, commit it to `fuzz/regressions/TARGET/`, where
//! `cargo xtask test` replays it.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context as _, Result, bail};

/// The cargo-fuzz release the command installs and expects.
const CARGO_FUZZ_VERSION: &str = "0.13.2";

#[derive(Debug, clap::Args)]
pub struct Args {
    /// The target: gltf_load, dsl_codegen or frame_graph.
    target: String,
    /// How long to fuzz.
    #[arg(long, default_value_t = 10.0)]
    minutes: f64,
    /// Stop after this many executions instead (0: no limit).
    #[arg(long, default_value_t = 0)]
    runs: u64,
}

#[expect(clippy::print_stdout, reason = "report of a command-line tool")]
pub fn run(args: &Args) -> Result<()> {
    if !fuzz::TARGETS.iter().any(|(name, _)| *name == args.target) {
        let names: Vec<&str> = fuzz::TARGETS.iter().map(|(n, _)| *n).collect();
        bail!(
            "no fuzz target `{}`; the targets are {names:?}",
            args.target
        );
    }
    if !(args.minutes > 0.0 && args.minutes.is_finite()) {
        bail!(
            "--minutes must be a positive number of minutes, not {}",
            args.minutes
        );
    }
    ensure_cargo_fuzz()?;
    let root = crate::workspace::workspace_root();
    let work = root.join("target/fuzz");
    let corpus = work.join("corpus").join(&args.target);
    let artifacts = work.join("artifacts").join(&args.target);
    std::fs::create_dir_all(&corpus)?;
    std::fs::create_dir_all(&artifacts)?;
    seed_corpus(
        &args.target,
        &corpus,
        &root.join("fuzz/regressions").join(&args.target),
    )?;
    let seconds = (args.minutes * 60.0).ceil() as u64;
    let log = work.join(format!("{}.log", args.target));
    println!(
        "fuzzing {} for {seconds} s (corpus {}, log {})",
        args.target,
        corpus.display(),
        log.display()
    );
    let mut libfuzzer = vec![
        format!("-max_total_time={seconds}"),
        "-timeout=1".to_owned(),
        "-rss_limit_mb=2048".to_owned(),
        "-max_len=1048576".to_owned(),
        "-print_final_stats=1".to_owned(),
        format!("-artifact_prefix={}/", artifacts.display()),
    ];
    if args.runs > 0 {
        libfuzzer.push(format!("-runs={}", args.runs));
    }
    let started = std::time::Instant::now();
    let run_start = std::time::SystemTime::now();
    let status = Command::new("cargo")
        .args([
            "fuzz",
            "run",
            "--fuzz-dir",
            "fuzz",
            "--features",
            "libfuzzer",
            // No ASan: the binaries' own allocator enforces the allocation limit, safe Rust
            // needs no address checks, and the build is smaller and quicker.
            "--sanitizer",
            "none",
        ])
        .arg(&args.target)
        .arg(&corpus)
        .arg("--")
        .args(&libfuzzer)
        .env("RUSTC_BOOTSTRAP", "1")
        .current_dir(&root)
        .stderr(std::fs::File::create(&log)?)
        .status()
        .context("running cargo fuzz")?;
    let text = std::fs::read_to_string(&log).unwrap_or_default();
    let stat = |name: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(&format!("stat::{name}:")))
            .map(|v| v.trim().to_owned())
    };
    let executions = stat("number_of_executed_units").unwrap_or_else(|| "?".into());
    let peak_rss = stat("peak_rss_mb").unwrap_or_else(|| "?".into());
    // Failing inputs of this run (earlier runs' stay in the folder until removed).
    let findings: Vec<PathBuf> = std::fs::read_dir(&artifacts)?
        .filter_map(|e| e.ok())
        .filter(|e| {
            e.metadata()
                .and_then(|m| m.modified())
                .is_ok_and(|t| t >= run_start)
        })
        .map(|e| e.path())
        .collect();
    println!(
        "{}: {executions} executions in {:.0} s, peak resident {peak_rss} MiB, corpus {} inputs, \
         {} failing inputs in {}",
        args.target,
        started.elapsed().as_secs_f64(),
        std::fs::read_dir(&corpus)?.count(),
        findings.len(),
        artifacts.display()
    );
    if !status.success() {
        let tail: Vec<&str> = text.lines().rev().take(40).collect();
        for line in tail.into_iter().rev() {
            println!("  {line}");
        }
        bail!(
            "the fuzzer stopped on a failure ({status}); the input is in {} and the log in {}",
            artifacts.display(),
            log.display()
        );
    }
    Ok(())
}

/// Installs cargo-fuzz at [`CARGO_FUZZ_VERSION`] unless that version is on the path.
fn ensure_cargo_fuzz() -> Result<()> {
    let installed = Command::new("cargo")
        .args(["fuzz", "--version"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned());
    if installed.is_some_and(|v| v.contains(CARGO_FUZZ_VERSION)) {
        return Ok(());
    }
    let status = Command::new("cargo")
        .args([
            "install",
            "cargo-fuzz",
            "--locked",
            "--version",
            CARGO_FUZZ_VERSION,
        ])
        .status()
        .context("running cargo install cargo-fuzz")?;
    if !status.success() {
        bail!("cargo install cargo-fuzz {CARGO_FUZZ_VERSION} failed ({status})");
    }
    Ok(())
}

/// Adds the target's seeds and committed regressions to its corpus.
fn seed_corpus(target: &str, corpus: &Path, regressions: &Path) -> Result<()> {
    if target == "gltf_load" {
        for (name, bytes) in fuzz::gltf_seeds::seeds() {
            std::fs::write(corpus.join(format!("seed-{name}")), bytes)?;
        }
    }
    if regressions.is_dir() {
        for entry in std::fs::read_dir(regressions)? {
            let path = entry?.path();
            if let Some(name) = path.file_name().filter(|n| *n != "README.md") {
                std::fs::copy(&path, corpus.join(name))?;
            }
        }
    }
    Ok(())
}
