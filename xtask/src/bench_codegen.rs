//! `cargo xtask bench-codegen`: how fast the shader DSL generates code, in-process and in a real
//! incremental build.
//!
//! 1. **Per variant**: the time to generate one variant, front end + variants + WGSL + naga
//!    validation + SPIR-V (+ reflection), as the proc-macro does, through the same entry point as
//!    `cargo xtask shaders` (`codegen::compile` on every `#[shader] mod` of `shaders_gen/src`).
//!    `codegen` times each distinct variant's own stages (`gen_time`: print, validate, SPIR-V,
//!    reflect); the rest of a module's compile (front end, key enumeration, printing the keys
//!    whose output duplicates an earlier variant) is shared, so each variant is charged
//!    `gen_time + shared ÷ variants`. Median, p90 and max over every variant of every module and
//!    every timed run (`--iters`, after one untimed warm-up run). Target: ≤ 2 ms.
//! 2. **Per module and in total**: wall time of `codegen::compile` (and of `codegen::emit::emit`,
//!    the tokens the macro returns), median over the runs.
//! 3. **Incremental rebuild**: `cargo build -p shaders_gen` (`--release` with `--release`) after a
//!    one-line change to the compute kernel of `shaders_gen/src/culling/tiled.rs`, median over
//!    `--rebuilds` builds after an untimed warm-up build; the edit alternates between two
//!    contents so each build really rebuilds (checked on cargo's output), the DSL is first shown
//!    to accept both in-process, and the file is restored byte-for-byte by a guard (on error and
//!    panic too) and checked. Then the same rebuild after a `touch` with no token change. The
//!    build inherits the environment (`CARGO_TARGET_DIR` included). A copy of the original waits
//!    in `target/bench/` while the file is edited, so that a run killed mid-build (Ctrl-C) is
//!    repaired by the next one.
//! 4. **Output size**: WGSL and SPIR-V bytes in total and per module, with the largest variant.
//!
//! The report names the machine (CPUs) and whether xtask, hence the in-process compiler, is a
//! debug or release build. It is printed as Markdown and written to `target/bench/codegen.md`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant, SystemTime};

use anyhow::{Context as _, Result, anyhow, bail, ensure};

use crate::shaders::{DslModule, check_all_modules_found, dsl_libraries, dsl_modules};

/// The target for one variant (median), in milliseconds.
const TARGET_MS_PER_VARIANT: f64 = 2.0;
/// The kernel edited for the incremental rebuild, relative to the workspace root.
const EDITED_FILE: &str = "shaders_gen/src/culling/tiled.rs";
/// Name of the variable the edit declares; also how a leftover edit is recognised.
const EDIT_MARKER: &str = "bench_codegen_edit";
/// Where the original of [`EDITED_FILE`] waits while it is edited, relative to the workspace root.
const BACKUP_FILE: &str = "target/bench/codegen-edit-backup.rs";

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Timed in-process runs over every variant (after one untimed warm-up run).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..))]
    iters: u32,
    /// Timed builds of shaders_gen after a one-line kernel edit (and as many after a touch).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..))]
    rebuilds: u32,
    /// Skip the incremental-rebuild measurement.
    #[arg(long)]
    no_rebuild: bool,
    /// Build shaders_gen with --release for the incremental-rebuild measurement.
    #[arg(long)]
    release: bool,
    /// Markdown report; defaults to target/bench/codegen.md.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// Median, p90 and max of a sample, in the sample's unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Stats {
    pub samples: usize,
    pub median: f64,
    pub p90: f64,
    pub max: f64,
}

impl Stats {
    fn of(values: &[f64]) -> Self {
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        Self {
            samples: sorted.len(),
            median: percentile(&sorted, 50.0),
            p90: percentile(&sorted, 90.0),
            max: percentile(&sorted, 100.0),
        }
    }
}

/// Figures of one `#[shader] mod`.
#[derive(Debug, Clone)]
pub(crate) struct ModuleFigures {
    pub name: String,
    /// Source file, relative to the workspace root.
    pub file: String,
    /// Keys of the axis matrix, excluded ones too.
    pub keys: usize,
    /// Distinct variants generated.
    pub variants: usize,
    pub wgsl_bytes: usize,
    pub spirv_bytes: usize,
    /// The variant with the most SPIR-V: (name, WGSL bytes, SPIR-V bytes).
    pub largest: (String, usize, usize),
    /// `codegen::compile`, median ms.
    pub compile_ms: f64,
    /// The shared part of it (front end, enumeration, duplicate keys), median ms.
    pub shared_ms: f64,
    /// `codegen::emit::emit`, median ms.
    pub emit_ms: f64,
}

/// Incremental builds of `shaders_gen`, in seconds.
#[derive(Debug, Clone)]
pub(crate) struct RebuildFigures {
    pub release: bool,
    /// The untimed build before the edits.
    pub warmup_s: f64,
    /// After the one-line kernel edit.
    pub edit_s: Vec<f64>,
    /// After a touch, tokens unchanged.
    pub touch_s: Vec<f64>,
}

/// Everything `bench-codegen` measures.
#[derive(Debug, Clone)]
pub(crate) struct Report {
    pub cpus: usize,
    pub cpu_model: Option<String>,
    pub rustc: Option<String>,
    /// 1-minute load average before and after the measurements (Linux): the machine is shared.
    pub load: (Option<f64>, Option<f64>),
    /// Whether xtask (the in-process compiler) is a debug build.
    pub debug: bool,
    pub iters: usize,
    /// Per variant, everything charged (`gen_time` + shared share), ms.
    pub per_variant: Stats,
    /// Per variant, `gen_time` only (what `cargo xtask shaders` prints), ms.
    pub per_variant_stages: Stats,
    pub modules: Vec<ModuleFigures>,
    /// Sum of every module's `codegen::compile`, median over the runs, ms.
    pub total_compile_ms: f64,
    /// Sum of every module's compile + emit, median over the runs, ms.
    pub total_expand_ms: f64,
    /// Compile + emit of the untimed warm-up run, ms.
    pub cold_expand_ms: f64,
    pub rebuild: Option<RebuildFigures>,
}

impl Report {
    fn variants(&self) -> usize {
        self.modules.iter().map(|m| m.variants).sum()
    }
}

pub fn run(args: &Args) -> Result<()> {
    let report = measure(args)?;
    let markdown = markdown(&report);
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| crate::workspace_root().join("target/bench/codegen.md"));
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    std::fs::write(&out, &markdown).with_context(|| format!("writing {}", out.display()))?;
    print_report(&markdown, &out);
    Ok(())
}

#[expect(clippy::print_stdout, reason = "command-line report")]
fn print_report(markdown: &str, out: &Path) {
    println!("{markdown}");
    println!("wrote {}", out.display());
}

/// Runs every measurement and returns the figures.
pub(crate) fn measure(args: &Args) -> Result<Report> {
    let root = crate::workspace_root();
    let load_before = load_average();
    let iters = args.iters.max(1) as usize;
    let modules = sources(&root)?;
    eprintln!(
        "bench-codegen: {} module(s), 1 warm-up + {iters} timed in-process run(s)",
        modules.len()
    );
    let cold = compile_all(&modules)?;
    let cold_expand_ms = cold.iter().map(|r| ms(r.compile + r.emit)).sum();
    let mut runs = Vec::with_capacity(iters);
    for _ in 0..iters {
        runs.push(compile_all(&modules)?);
    }

    let mut per_variant = Vec::new();
    let mut per_variant_stages = Vec::new();
    for run in &runs {
        for r in run {
            let n = r.gen_times.len();
            let gen_total: Duration = r.gen_times.iter().sum();
            let shared = r.compile.saturating_sub(gen_total);
            for &g in &r.gen_times {
                per_variant.push(ms(g) + ms(shared) / n as f64);
                per_variant_stages.push(ms(g));
            }
        }
    }
    let figures = modules
        .iter()
        .zip(&cold)
        .enumerate()
        .map(|(i, (m, sizes))| {
            let median_of = |f: &dyn Fn(&ModuleRun) -> f64| {
                Stats::of(&runs.iter().map(|run| f(&run[i])).collect::<Vec<_>>()).median
            };
            ModuleFigures {
                name: m.item.ident.to_string(),
                file: m
                    .file
                    .strip_prefix(&root)
                    .unwrap_or(&m.file)
                    .display()
                    .to_string(),
                keys: sizes.keys,
                variants: sizes.gen_times.len(),
                wgsl_bytes: sizes.wgsl.iter().sum(),
                spirv_bytes: sizes.spirv.iter().sum(),
                largest: sizes.largest.clone(),
                compile_ms: median_of(&|r| ms(r.compile)),
                shared_ms: median_of(&|r| ms(r.compile.saturating_sub(r.gen_times.iter().sum()))),
                emit_ms: median_of(&|r| ms(r.emit)),
            }
        })
        .collect();
    let sum_of = |f: &dyn Fn(&ModuleRun) -> f64| {
        let totals: Vec<f64> = runs.iter().map(|run| run.iter().map(f).sum()).collect();
        Stats::of(&totals).median
    };

    let rebuild = if args.no_rebuild {
        None
    } else {
        Some(measure_rebuild(&root, args.release, args.rebuilds.max(1))?)
    };
    Ok(Report {
        cpus: std::thread::available_parallelism().map_or(1, std::num::NonZero::get),
        cpu_model: cpu_model(),
        rustc: rustc_version(),
        load: (load_before, load_average()),
        debug: cfg!(debug_assertions),
        iters,
        per_variant: Stats::of(&per_variant),
        per_variant_stages: Stats::of(&per_variant_stages),
        modules: figures,
        total_compile_ms: sum_of(&|r| ms(r.compile)),
        total_expand_ms: sum_of(&|r| ms(r.compile + r.emit)),
        cold_expand_ms,
        rebuild,
    })
}

/// A `#[shader] mod` of `shaders_gen`, parsed once.
struct Source {
    file: PathBuf,
    args: proc_macro2::TokenStream,
    item: syn::ItemMod,
    /// Every library of `shaders_gen`, for the module's `uses(..)`.
    libraries: Vec<DslModule>,
}

fn sources(root: &Path) -> Result<Vec<Source>> {
    let found = dsl_modules(&root.join("shaders_gen/src"))?;
    check_all_modules_found(&found)?;
    let libraries = shaders_gen_libraries(root)?;
    Ok(found
        .into_iter()
        .flat_map(|(file, modules)| {
            let libraries = libraries.clone();
            modules.into_iter().map(move |(args, item)| Source {
                file: file.clone(),
                args,
                item,
                libraries: libraries.clone(),
            })
        })
        .collect())
}

/// The `#[library]` modules of `shaders_gen`.
fn shaders_gen_libraries(root: &Path) -> Result<Vec<DslModule>> {
    Ok(dsl_libraries(&root.join("shaders_gen/src"))?
        .into_iter()
        .map(|(_, m)| m)
        .collect())
}

/// One module of one in-process run.
struct ModuleRun {
    compile: Duration,
    emit: Duration,
    keys: usize,
    gen_times: Vec<Duration>,
    wgsl: Vec<usize>,
    spirv: Vec<usize>,
    largest: (String, usize, usize),
}

fn compile_all(modules: &[Source]) -> Result<Vec<ModuleRun>> {
    modules
        .iter()
        .map(|m| {
            let args = m.args.clone();
            let start = Instant::now();
            let compiled = codegen::compile_with_libraries(args, &m.item, &m.libraries)
                .map_err(|e| anyhow!("{}: module `{}`: {e}", m.file.display(), m.item.ident))?;
            let compile = start.elapsed();
            let start = Instant::now();
            let tokens = codegen::emit::emit(&m.item, &compiled);
            let emit = start.elapsed();
            std::hint::black_box(tokens);
            let largest = compiled
                .variants
                .iter()
                .max_by_key(|v| v.spirv.len())
                .map(|v| (v.names[0].clone(), v.wgsl.len(), v.spirv.len() * 4))
                .unwrap_or_default();
            Ok(ModuleRun {
                compile,
                emit,
                keys: compiled.keys.len(),
                gen_times: compiled.variants.iter().map(|v| v.gen_time).collect(),
                wgsl: compiled.variants.iter().map(|v| v.wgsl.len()).collect(),
                spirv: compiled
                    .variants
                    .iter()
                    .map(|v| v.spirv.len() * 4)
                    .collect(),
                largest,
            })
        })
        .collect()
}

fn measure_rebuild(root: &Path, release: bool, rebuilds: u32) -> Result<RebuildFigures> {
    let path = root.join(EDITED_FILE);
    let backup = root.join(BACKUP_FILE);
    recover_interrupted_edit(&path, &backup)?;
    let original =
        std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
    let edits = [edited_source(&original, 0)?, edited_source(&original, 1)?];
    let libraries = shaders_gen_libraries(root)?;
    for edit in &edits {
        check_dsl_accepts(edit, &libraries)
            .context("the DSL rejects the benchmark's one-line kernel edit")?;
    }
    let profile = if release { "release" } else { "debug" };
    eprintln!("bench-codegen: warm-up `cargo build -p shaders_gen` ({profile}, untimed)");
    let warmup = cargo_build(root, release, false)?;

    let mut edit_s = Vec::new();
    {
        let guard = RestoreGuard::new(&path, Some(&backup))?;
        for i in 0..rebuilds as usize {
            guard.write(edits[i % 2].as_bytes())?;
            let t = cargo_build(root, release, true)?;
            eprintln!(
                "bench-codegen: rebuild {}/{rebuilds} after the edit: {:.2} s",
                i + 1,
                t.as_secs_f64()
            );
            edit_s.push(t.as_secs_f64());
        }
        guard.restore()?;
    }

    // The restored file is newer than the last build, so this one brings the build back in line
    // with the sources before the touches are timed.
    cargo_build(root, release, true)?;
    let mut touch_s = Vec::new();
    for i in 0..rebuilds {
        touch(&path)?;
        let t = cargo_build(root, release, true)?;
        eprintln!(
            "bench-codegen: rebuild {}/{rebuilds} after a touch: {:.2} s",
            i + 1,
            t.as_secs_f64()
        );
        touch_s.push(t.as_secs_f64());
    }
    Ok(RebuildFigures {
        release,
        warmup_s: warmup.as_secs_f64(),
        edit_s,
        touch_s,
    })
}

/// `source` with one statement added at the top of the body of its first `#[compute]` function:
/// `let bench_codegen_edit = <value>u32;`. Different values give different macro input tokens.
fn edited_source(source: &str, value: u32) -> Result<String> {
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
fn check_dsl_accepts(source: &str, libraries: &[DslModule]) -> Result<()> {
    let file = syn::parse_file(source)?;
    let modules = codegen::shader_modules(&file);
    ensure!(!modules.is_empty(), "no `#[shader] mod` found");
    for (args, item) in modules {
        codegen::compile_with_libraries(args, &item, libraries)
            .map_err(|e| anyhow!("module `{}`: {e}", item.ident))?;
    }
    Ok(())
}

/// Repairs the edited file after a run that was killed before its guard could restore it.
fn recover_interrupted_edit(path: &Path, backup: &Path) -> Result<()> {
    let current = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    if !contains(&current, EDIT_MARKER.as_bytes()) {
        return Ok(());
    }
    match std::fs::read(backup) {
        Ok(saved) if !contains(&saved, EDIT_MARKER.as_bytes()) => {
            restore_exact(path, &saved)?;
            std::fs::remove_file(backup)?;
            eprintln!(
                "bench-codegen: {} still held an interrupted run's edit; restored it from {}",
                path.display(),
                backup.display()
            );
            Ok(())
        }
        _ => bail!(
            "{} contains `{EDIT_MARKER}` (an interrupted bench-codegen run?) and there is no \
             backup in {}: restore it, e.g. with `git checkout -- {EDITED_FILE}`",
            path.display(),
            backup.display()
        ),
    }
}

fn contains(haystack: &[u8], needle: &[u8]) -> bool {
    haystack.windows(needle.len()).any(|w| w == needle)
}

/// Writes `bytes` to `path` and reads them back.
fn restore_exact(path: &Path, bytes: &[u8]) -> Result<()> {
    std::fs::write(path, bytes).with_context(|| format!("restoring {}", path.display()))?;
    let back = std::fs::read(path).with_context(|| format!("reading back {}", path.display()))?;
    ensure!(
        back == bytes,
        "{} differs from its original after the restore",
        path.display()
    );
    Ok(())
}

/// Holds a file's original bytes while the file is edited, and restores them exactly when
/// dropped: on success, error or panic. [`RestoreGuard::restore`] does it explicitly and reports
/// failure. An optional backup copy on disk survives a killed process.
#[derive(Debug)]
struct RestoreGuard {
    path: PathBuf,
    original: Vec<u8>,
    backup: Option<PathBuf>,
    armed: bool,
}

impl RestoreGuard {
    fn new(path: &Path, backup: Option<&Path>) -> Result<Self> {
        let original =
            std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
        if let Some(backup) = backup {
            if let Some(dir) = backup.parent() {
                std::fs::create_dir_all(dir)?;
            }
            std::fs::write(backup, &original)
                .with_context(|| format!("writing {}", backup.display()))?;
        }
        Ok(Self {
            path: path.to_path_buf(),
            original,
            backup: backup.map(Path::to_path_buf),
            armed: true,
        })
    }

    fn write(&self, contents: &[u8]) -> Result<()> {
        std::fs::write(&self.path, contents)
            .with_context(|| format!("writing {}", self.path.display()))
    }

    /// Restores the original bytes and checks them.
    fn restore(mut self) -> Result<()> {
        self.armed = false;
        restore_exact(&self.path, &self.original)?;
        if let Some(backup) = &self.backup {
            std::fs::remove_file(backup)
                .with_context(|| format!("removing {}", backup.display()))?;
        }
        Ok(())
    }
}

impl Drop for RestoreGuard {
    fn drop(&mut self) {
        if !self.armed {
            return;
        }
        match restore_exact(&self.path, &self.original) {
            Ok(()) => {
                if let Some(backup) = &self.backup {
                    let _ = std::fs::remove_file(backup);
                }
            }
            Err(e) => eprintln!(
                "bench-codegen: could not restore {}: {e:#}{}",
                self.path.display(),
                self.backup
                    .as_ref()
                    .map(|b| format!("; its original is in {}", b.display()))
                    .unwrap_or_default()
            ),
        }
    }
}

fn touch(path: &Path) -> Result<()> {
    std::fs::File::options()
        .write(true)
        .open(path)
        .and_then(|f| f.set_modified(SystemTime::now()))
        .with_context(|| format!("touching {}", path.display()))
}

/// Times `cargo build -p shaders_gen`, with the caller's environment. With `expect_rebuild`, fails
/// when cargo did not recompile shaders_gen (the measurement would be of a no-op).
fn cargo_build(root: &Path, release: bool, expect_rebuild: bool) -> Result<Duration> {
    let mut command = Command::new(env!("CARGO"));
    command
        .current_dir(root)
        .args(["build", "-p", "shaders_gen", "--color", "never"]);
    if release {
        command.arg("--release");
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

/// The `p`-th percentile (0 to 100) of sorted values, interpolated between the closest ranks;
/// NaN when empty.
fn percentile(sorted: &[f64], p: f64) -> f64 {
    match sorted.len() {
        0 => f64::NAN,
        n => {
            let rank = (p / 100.0).clamp(0.0, 1.0) * (n - 1) as f64;
            let (lo, hi) = (rank.floor() as usize, rank.ceil() as usize);
            sorted[lo] + (sorted[hi] - sorted[lo]) * (rank - lo as f64)
        }
    }
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn cpu_model() -> Option<String> {
    let info = std::fs::read_to_string("/proc/cpuinfo").ok()?;
    info.lines()
        .find_map(|l| l.strip_prefix("model name")?.split_once(':'))
        .map(|(_, m)| m.trim().to_owned())
}

fn load_average() -> Option<f64> {
    std::fs::read_to_string("/proc/loadavg")
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

fn rustc_version() -> Option<String> {
    let rustc = std::env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
    let out = Command::new(rustc).arg("-V").output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_owned())
}

/// The report as Markdown.
fn markdown(r: &Report) -> String {
    let mut s = String::new();
    // Writing to a String cannot fail.
    let _ = write_markdown(&mut s, r);
    s
}

fn write_markdown(s: &mut String, r: &Report) -> std::fmt::Result {
    let build = if r.debug {
        "debug (dev profile; codegen and naga at opt-level 3)"
    } else {
        "release"
    };
    writeln!(s, "# Code generation benchmark\n")?;
    writeln!(
        s,
        "- Machine: {} CPU(s){}",
        r.cpus,
        r.cpu_model
            .as_deref()
            .map(|m| format!(", {m}"))
            .unwrap_or_default()
    )?;
    writeln!(s, "- xtask build (in-process compiler): {build}")?;
    if r.debug {
        writeln!(
            s,
            "- Note: this dev build of xtask leaves syn, proc-macro2 and quote unoptimised, while \
             the proc-macro gets them at opt-level 3 (`[profile.dev.build-override]`), so the \
             shared and emit times overstate the macro's"
        )?;
    }
    if let Some(v) = &r.rustc {
        writeln!(s, "- Toolchain: {v}")?;
    }
    let load = |l: Option<f64>| l.map_or_else(|| "?".to_owned(), |l| format!("{l:.2}"));
    writeln!(
        s,
        "- Load average (1 min) before / after: {} / {} (other work on the machine skews the \
         timings)",
        load(r.load.0),
        load(r.load.1)
    )?;
    writeln!(
        s,
        "- In-process: {} module(s), {} variant(s) ({} key(s)); 1 untimed warm-up run, then {} \
         timed run(s)\n",
        r.modules.len(),
        r.variants(),
        r.modules.iter().map(|m| m.keys).sum::<usize>(),
        r.iters
    )?;

    writeln!(s, "## Time per variant\n")?;
    writeln!(s, "| what | samples | median ms | p90 ms | max ms |")?;
    writeln!(s, "|---|---:|---:|---:|---:|")?;
    for (what, st) in [
        (
            "front end + variants + WGSL + naga + SPIR-V (shared part spread over the module's variants)",
            r.per_variant,
        ),
        (
            "WGSL + naga + SPIR-V + reflect only (`gen_time`, as `cargo xtask shaders`)",
            r.per_variant_stages,
        ),
    ] {
        writeln!(
            s,
            "| {what} | {} | {:.3} | {:.3} | {:.3} |",
            st.samples, st.median, st.p90, st.max
        )?;
    }
    let verdict = |v: f64| {
        if v <= TARGET_MS_PER_VARIANT {
            "met"
        } else {
            "NOT met"
        }
    };
    writeln!(
        s,
        "\nTarget ≤ {TARGET_MS_PER_VARIANT} ms per variant: median {}, p90 {}, max {}.\n",
        verdict(r.per_variant.median),
        verdict(r.per_variant.p90),
        verdict(r.per_variant.max)
    )?;

    writeln!(s, "## Per module (times: median over the timed runs)\n")?;
    writeln!(
        s,
        "| module | file | keys | variants | compile ms | of which shared ms | emit ms | WGSL bytes | SPIR-V bytes | largest variant (WGSL / SPIR-V bytes) |"
    )?;
    writeln!(s, "|---|---|---:|---:|---:|---:|---:|---:|---:|---|")?;
    for m in &r.modules {
        writeln!(
            s,
            "| {} | {} | {} | {} | {:.2} | {:.2} | {:.2} | {} | {} | {} ({} / {}) |",
            m.name,
            m.file,
            m.keys,
            m.variants,
            m.compile_ms,
            m.shared_ms,
            m.emit_ms,
            m.wgsl_bytes,
            m.spirv_bytes,
            m.largest.0,
            m.largest.1,
            m.largest.2
        )?;
    }
    let largest = r
        .modules
        .iter()
        .max_by_key(|m| m.largest.2)
        .map(|m| {
            format!(
                "{}::{} ({} / {})",
                m.name, m.largest.0, m.largest.1, m.largest.2
            )
        })
        .unwrap_or_default();
    writeln!(
        s,
        "| **total** | | {} | {} | {:.2} | | {:.2} | {} | {} | {largest} |\n",
        r.modules.iter().map(|m| m.keys).sum::<usize>(),
        r.variants(),
        r.total_compile_ms,
        r.total_expand_ms - r.total_compile_ms,
        r.modules.iter().map(|m| m.wgsl_bytes).sum::<usize>(),
        r.modules.iter().map(|m| m.spirv_bytes).sum::<usize>(),
    )?;
    writeln!(
        s,
        "Wall time for every variant of shaders_gen, in-process (median of the runs' totals): \
         compile {:.1} ms, compile + emit {:.1} ms; the untimed first (cold) run: compile + emit \
         {:.1} ms.\n",
        r.total_compile_ms, r.total_expand_ms, r.cold_expand_ms
    )?;

    writeln!(s, "## Incremental rebuild of shaders_gen\n")?;
    match &r.rebuild {
        None => writeln!(s, "Skipped (`--no-rebuild`).")?,
        Some(b) => {
            let flag = if b.release { " --release" } else { "" };
            writeln!(
                s,
                "`cargo build -p shaders_gen{flag}`, environment inherited; untimed warm-up build \
                 {:.2} s.\n",
                b.warmup_s
            )?;
            if b.release {
                writeln!(
                    s,
                    "In release, Cargo builds the proc-macro and its dependencies (codegen, naga) \
                     at opt-level 0 unless `[profile.release.build-override]` says otherwise.\n"
                )?;
            }
            writeln!(s, "| change | builds | median s | min s | max s | each s |")?;
            writeln!(s, "|---|---:|---:|---:|---:|---|")?;
            for (what, times) in [
                (
                    format!("one-line kernel edit in `{EDITED_FILE}`"),
                    &b.edit_s,
                ),
                ("touch, no token change".to_owned(), &b.touch_s),
            ] {
                let st = Stats::of(times);
                let min = times.iter().copied().fold(f64::INFINITY, f64::min);
                let each: Vec<String> = times.iter().map(|t| format!("{t:.2}")).collect();
                writeln!(
                    s,
                    "| {what} | {} | {:.2} | {min:.2} | {:.2} | {} |",
                    st.samples,
                    st.median,
                    st.max,
                    each.join(", ")
                )?;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_file(name: &str, bytes: &[u8]) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("xtask-bench-codegen-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    }

    /// Not UTF-8, CRLF and no final newline: restored byte for byte all the same.
    const ORIGINAL: &[u8] = b"fn main() {\r\n    let x = 1;\xff\xfe\n}";

    #[test]
    fn guard_restores_the_exact_bytes_on_drop() {
        let path = temp_file("drop.rs", ORIGINAL);
        let backup = path.with_extension("backup");
        {
            let guard = RestoreGuard::new(&path, Some(&backup)).unwrap();
            assert_eq!(std::fs::read(&backup).unwrap(), ORIGINAL);
            guard.write(b"edited").unwrap();
            assert_eq!(std::fs::read(&path).unwrap(), b"edited");
        }
        assert_eq!(std::fs::read(&path).unwrap(), ORIGINAL);
        assert!(!backup.exists(), "the backup is removed once restored");
    }

    #[test]
    fn guard_restores_on_panic() {
        let path = temp_file("panic.rs", ORIGINAL);
        let result = std::panic::catch_unwind(|| {
            let guard = RestoreGuard::new(&path, None).unwrap();
            guard.write(b"edited").unwrap();
            panic!("build failed");
        });
        assert!(result.is_err());
        assert_eq!(std::fs::read(&path).unwrap(), ORIGINAL);
    }

    #[test]
    fn explicit_restore_checks_and_disarms() {
        let path = temp_file("restore.rs", ORIGINAL);
        let guard = RestoreGuard::new(&path, None).unwrap();
        guard.write(b"edited").unwrap();
        guard.restore().unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), ORIGINAL);
    }

    #[test]
    fn interrupted_edit_is_recovered_from_the_backup() {
        let path = temp_file("interrupted.rs", b"let bench_codegen_edit = 0u32;");
        let backup = temp_file("interrupted.backup", ORIGINAL);
        recover_interrupted_edit(&path, &backup).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), ORIGINAL);
        assert!(!backup.exists());
        // Without a backup it refuses rather than guessing.
        std::fs::write(&path, b"let bench_codegen_edit = 0u32;").unwrap();
        assert!(recover_interrupted_edit(&path, &backup).is_err());
        // An unedited file is left alone.
        std::fs::write(&path, ORIGINAL).unwrap();
        recover_interrupted_edit(&path, &backup).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), ORIGINAL);
    }

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
        let src = std::fs::read_to_string(crate::workspace_root().join(EDITED_FILE)).unwrap();
        assert!(!src.contains(EDIT_MARKER));
        let libraries = shaders_gen_libraries(&crate::workspace_root()).unwrap();
        for value in [0, 1] {
            check_dsl_accepts(&edited_source(&src, value).unwrap(), &libraries).unwrap();
        }
    }
}
