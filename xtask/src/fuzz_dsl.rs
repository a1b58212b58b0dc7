//! `cargo xtask fuzz-dsl`: the generated differential test of DSL expressions
//! (`tests::dsl_fuzz`) with more cases than `cargo test` runs, printing every failure shrunk.

use anyhow::{Result, bail};
use tests::dsl_fuzz::{Config, fuzz};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Number of expressions to generate.
    #[arg(long, default_value_t = 20_000)]
    cases: usize,
    /// Seed of the run (the test uses the default).
    #[arg(long, default_value_t = Config::default().seed)]
    seed: u64,
    /// Maximum expression depth.
    #[arg(long, default_value_t = Config::default().depth)]
    depth: u32,
    /// Generate shift amounts not masked to 0..32.
    #[arg(long)]
    raw_shifts: bool,
    /// Compare "exact" float results bit-for-bit (no 1-ULP slack).
    #[arg(long)]
    strict: bool,
}

#[expect(clippy::print_stdout, reason = "report of a command-line tool")]
pub fn run(args: &Args) -> Result<()> {
    let cfg = Config {
        seed: args.seed,
        cases: args.cases,
        depth: args.depth,
        raw_shifts: args.raw_shifts,
        ..Config::default()
    };
    tests::dsl_fuzz::run::EXACT_SLACK_ULPS_STRICT
        .store(args.strict, std::sync::atomic::Ordering::Relaxed);
    let started = std::time::Instant::now();
    let report = tests::gpu::gpu_test(|gpu| {
        fuzz(gpu, &cfg, |r| {
            eprint!(
                "\r{} / {} expressions, {} failures",
                r.expressions,
                cfg.cases,
                r.failures.len()
            );
        })
    });
    eprintln!();
    for f in &report.failures {
        println!("{f}\n");
    }
    println!(
        "fuzz-dsl seed {}: {} expressions, {} input rows compared, {} skipped, {} failures in {:.1} s",
        cfg.seed,
        report.expressions,
        report.rows_compared,
        report.rows_skipped,
        report.failures.len(),
        started.elapsed().as_secs_f64()
    );
    if !report.failures.is_empty() {
        bail!("{} failure(s)", report.failures.len());
    }
    Ok(())
}
