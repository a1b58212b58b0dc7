//! Generated differential test of DSL expressions and statement programs (see
//! `tests::dsl_fuzz`): a fixed seed of random cases, compiled through `codegen`, run on the GPU
//! and compared three ways: with the host evaluator `codegen::interp` (which runs the IR of the
//! same front end), and with the host-Rust oracle (the same cases printed as plain Rust over
//! the guide's semantics, compiled with `rustc`: no DSL front end). `cargo xtask fuzz-dsl
//! --cases N [--seed S]` runs more.

use tests::dsl_fuzz::statements::fuzz_programs;
use tests::dsl_fuzz::{Config, fuzz};
use tests::gpu::gpu_test;

#[test]
fn generated_expressions_match_the_host_evaluator_and_the_rust_oracle() {
    let cfg = Config::default();
    let started = std::time::Instant::now();
    let report = gpu_test(|gpu| fuzz(gpu, &cfg, |_| {}));
    eprintln!(
        "{} expressions, {} rows compared, {} skipped, {} also with the Rust oracle, {} \
         failures, {:.1} s",
        report.expressions,
        report.rows_compared,
        report.rows_skipped,
        report.oracle_rows,
        report.failures.len(),
        started.elapsed().as_secs_f64()
    );
    assert!(report.failures.is_empty(), "{}", report.failures_text(8));
    assert!(
        report.rows_compared > report.expressions * 32,
        "too many rows skipped"
    );
    assert!(
        report.oracle_rows > report.rows_compared * 3 / 4,
        "too few rows compared with the Rust oracle"
    );
}

#[test]
fn generated_statement_programs_match_the_host_interpreter_and_the_rust_oracle() {
    let cfg = Config {
        cases: 512,
        ..Config::default()
    };
    let started = std::time::Instant::now();
    let report = gpu_test(|gpu| fuzz_programs(gpu, &cfg, |_| {}));
    eprintln!(
        "{} statement programs, {} rows compared, {} also with the Rust oracle, {} failures, \
         {:.1} s",
        report.expressions,
        report.rows_compared,
        report.oracle_rows,
        report.failures.len(),
        started.elapsed().as_secs_f64()
    );
    assert!(report.failures.is_empty(), "{}", report.failures_text(8));
    assert_eq!(report.expressions, cfg.cases);
    assert_eq!(report.oracle_rows, report.rows_compared);
}

/// Shrunk findings of `fuzz-dsl`, kept as fixed cases with the inputs that exposed them.
#[test]
fn fuzz_findings_stay_fixed_on_the_gpu() {
    use tests::dsl_fuzz::ast::{E, Kind, Sc, T, Tol};
    use tests::dsl_fuzz::oracle;
    use tests::dsl_fuzz::run::{Outcome, ROWS, WORDS, compare, compile, run_gpu};
    let leaf = |s: Sc, i: usize| E {
        ty: T::scalar(s),
        kind: Kind::Input(i),
    };
    let i32_ty = T::scalar(Sc::I32);
    let abs = |x: E| E {
        ty: i32_ty,
        kind: Kind::Method("abs", Box::new(x), vec![]),
    };
    // `(i3.abs() >> u0).abs()` with i3 = i32::MIN: lavapipe took SPIR-V's SAbs to be
    // non-negative and dropped the outer abs (-256 instead of 256). Printed through the
    // `dsl_abs_i32` helper now.
    let shifted = E {
        ty: i32_ty,
        kind: Kind::Bin(
            ">>",
            Box::new(abs(leaf(Sc::I32, 3))),
            Box::new(leaf(Sc::U32, 0)),
        ),
    };
    let x = abs(shifted);
    let mut inputs = vec![0u32; ROWS * WORDS];
    for row in 0..ROWS {
        inputs[row * WORDS + 3] = i32::MIN as u32;
        inputs[row * WORDS + 4] = row as u32 % 32;
    }
    let rows = oracle::expressions(&[&x], &[0], std::slice::from_ref(&inputs)).expect("oracle");
    gpu_test(|gpu| {
        let c = compile(&[&x]).expect("compiles");
        assert!(c.wgsl.contains("fn dsl_abs_i32"), "{}", c.wgsl);
        let out = run_gpu(gpu, &c.wgsl, &inputs, 1);
        let o = compare(
            &c,
            0,
            i32_ty,
            Tol::Exact,
            &inputs,
            &out,
            0,
            1,
            Some(&rows[0]),
        );
        assert!(
            matches!(
                o,
                Outcome::Agree {
                    compared: ROWS,
                    oracle: ROWS,
                    ..
                }
            ),
            "{}: {o:?}",
            x.source()
        );
    });
}
