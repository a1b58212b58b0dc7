//! Generated differential test of DSL expressions (see `tests::dsl_fuzz`): a fixed seed of
//! random expression programs, compiled through `codegen`, run on the GPU and compared with
//! the host evaluator `codegen::interp`. `cargo xtask fuzz-dsl --cases N [--seed S]` runs more.

use tests::dsl_fuzz::statements::fuzz_programs;
use tests::dsl_fuzz::{Config, fuzz};
use tests::gpu::gpu_test;

#[test]
fn generated_expressions_match_the_host_evaluator() {
    let cfg = Config::default();
    let report = gpu_test(|gpu| fuzz(gpu, &cfg, |_| {}));
    eprintln!(
        "{} expressions, {} rows compared, {} skipped, {} failures",
        report.expressions,
        report.rows_compared,
        report.rows_skipped,
        report.failures.len()
    );
    let text: Vec<String> = report.failures.iter().map(|f| f.to_string()).collect();
    assert!(report.failures.is_empty(), "{}", text.join("\n\n"));
    assert!(
        report.rows_compared > report.expressions * 32,
        "too many rows skipped"
    );
}

#[test]
fn generated_statement_programs_match_the_host_interpreter() {
    let cfg = Config {
        cases: 512,
        ..Config::default()
    };
    let report = gpu_test(|gpu| fuzz_programs(gpu, &cfg, |_| {}));
    eprintln!(
        "{} statement programs, {} rows compared, {} failures",
        report.expressions,
        report.rows_compared,
        report.failures.len()
    );
    let text: Vec<String> = report.failures.iter().map(|f| f.to_string()).collect();
    assert!(report.failures.is_empty(), "{}", text.join("\n\n"));
    assert_eq!(report.expressions, cfg.cases);
}
