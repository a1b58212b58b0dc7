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
//!    contents so each build really rebuilds (checked on cargo's output), and the DSL is first
//!    shown to accept both in-process. Then the same rebuild after a `touch` with no token change.
//!    The edits and touches go to a copy of `shaders_gen` in a scratch workspace under
//!    `target/bench/` ([`scratch`]), never to the checkout, so a run that fails or is killed
//!    (Ctrl-C) leaves the checkout as it was. The build inherits the environment
//!    (`CARGO_TARGET_DIR` included) and shares the checkout's build folder for the dependencies.
//! 4. **Output size**: WGSL and SPIR-V bytes in total and per module, with the largest variant.
//!
//! The report names the machine (CPUs) and whether xtask, hence the in-process compiler, is a
//! debug or release build. It is printed as Markdown ([`report`]) and written to
//! `target/bench/codegen.md`. The rebuilds are in [`rebuild`].

mod figures;
mod rebuild;
mod report;
mod scratch;
#[cfg(test)]
mod tests;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use anyhow::{Context as _, Result, anyhow};

use self::figures::{ModuleFigures, RebuildFigures, Report, Stats};
use self::rebuild::measure_rebuild;
use self::report::markdown;
use crate::shaders::{DslModule, check_all_modules_found, dsl_libraries, dsl_modules};

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

pub fn run(args: &Args) -> Result<()> {
    let report = measure(args)?;
    let markdown = markdown(&report);
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| crate::workspace::workspace_root().join("target/bench/codegen.md"));
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
    let root = crate::workspace::workspace_root();
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
        let libraries = shaders_gen_libraries(&root)?;
        let times = measure_rebuild(&root, args.release, args.rebuilds.max(1), &libraries)?;
        Some(RebuildFigures {
            release: args.release,
            warmup_s: times.warmup_s,
            edit_s: times.edit_s,
            touch_s: times.touch_s,
        })
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
