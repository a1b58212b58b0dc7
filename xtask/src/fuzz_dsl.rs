//! `cargo xtask fuzz-dsl`: the generated differential tests of DSL expressions and statement
//! programs (`tests::dsl_fuzz`) with more cases than `cargo test` runs, printing every failure
//! shrunk. The GPU is compared with the host interpreter and with the host-Rust oracle (the
//! cases compiled as plain Rust by `rustc`; `--no-oracle` leaves it out).

use anyhow::{Result, bail};
use tests::dsl_fuzz::statements::fuzz_programs;
use tests::dsl_fuzz::{Config, Report, fuzz};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Number of expressions to generate.
    #[arg(long, default_value_t = 20_000)]
    cases: usize,
    /// Number of statement programs to generate (after the expressions).
    #[arg(long, default_value_t = 2_000)]
    statements: usize,
    /// Seed of the run (the test uses the default).
    #[arg(long, default_value_t = Config::default().seed)]
    seed: u64,
    /// Maximum expression depth.
    #[arg(long, default_value_t = Config::default().depth)]
    depth: u32,
    /// Generate shift amounts not masked to 0..32.
    #[arg(long)]
    raw_shifts: bool,
    /// Compare "exact" float results bit for bit (no allowance for the driver's regrouping of
    /// float operations).
    #[arg(long)]
    strict: bool,
    /// Leave out the host-Rust oracle (no `rustc` runs).
    #[arg(long)]
    no_oracle: bool,
}

#[expect(clippy::print_stdout, reason = "report of a command-line tool")]
pub fn run(args: &Args) -> Result<()> {
    let cfg = Config {
        seed: args.seed,
        cases: args.cases,
        depth: args.depth,
        raw_shifts: args.raw_shifts,
        oracle: !args.no_oracle,
        ..Config::default()
    };
    tests::dsl_fuzz::run::EXACT_SLACK_ULPS_STRICT
        .store(args.strict, std::sync::atomic::Ordering::Relaxed);
    let started = std::time::Instant::now();
    let (expressions, programs) = tests::gpu::gpu_test(|gpu| {
        let e = fuzz(gpu, &cfg, |r| {
            eprint!(
                "\r{} / {} expressions, {} failures",
                r.expressions,
                cfg.cases,
                r.failures.len()
            );
        });
        eprintln!();
        let stmt_cfg = Config {
            cases: args.statements,
            ..cfg
        };
        let p = fuzz_programs(gpu, &stmt_cfg, |r| {
            eprint!(
                "\r{} / {} statement programs, {} failures",
                r.expressions,
                stmt_cfg.cases,
                r.failures.len()
            );
        });
        eprintln!();
        (e, p)
    });
    let mut failures = 0;
    for (what, report) in [
        ("expressions", &expressions),
        ("statement programs", &programs),
    ] {
        for f in &report.failures {
            println!("{f}\n");
        }
        summary(cfg.seed, what, report);
        failures += report.failures.len();
    }
    println!("in {:.1} s", started.elapsed().as_secs_f64());
    if failures > 0 {
        bail!("{failures} failure(s)");
    }
    Ok(())
}

#[expect(clippy::print_stdout, reason = "report of a command-line tool")]
fn summary(seed: u64, what: &str, r: &Report) {
    println!(
        "fuzz-dsl seed {seed}: {} {what}, {} input rows compared ({} also with the Rust \
         oracle), {} skipped, {} failures",
        r.expressions,
        r.rows_compared,
        r.oracle_rows,
        r.rows_skipped,
        r.failures.len(),
    );
}
