//! The expression run: batches of generated expressions on the GPU, compared with the
//! interpreter and the host-Rust oracle, and every failure shrunk.

use super::ast::{E, Tol};
use super::generate::{Rng, shrink_candidates};
use super::oracle::{self, Row};
use super::run::{self, Outcome};
use super::{Config, Failure, Report, programs};
use renderer::GpuContext;

/// Oracle failures shrunk per run; later ones are reported as found.
const ORACLE_SHRINKS: usize = 3;

/// Runs a batch: per expression, its outcome, or the compile error of the whole batch.
fn run_batch(
    gpu: &GpuContext,
    exprs: &[(E, Tol)],
    inputs: &[u32],
    oracle: Option<&[Vec<Row>]>,
) -> Result<Vec<Outcome>, String> {
    let refs: Vec<&E> = exprs.iter().map(|x| &x.0).collect();
    let c = run::compile(&refs)?;
    let stride: usize = refs.iter().map(|x| x.ty.n as usize).sum::<usize>().max(1);
    let out = run::run_gpu(gpu, &c.wgsl, inputs, stride);
    let mut slot = 0;
    Ok(exprs
        .iter()
        .enumerate()
        .map(|(k, (x, tol))| {
            let rows = oracle.map(|o| o[k].as_slice());
            let o = run::compare(&c, k, x.ty, *tol, inputs, &out, slot, stride, rows);
            slot += x.ty.n as usize;
            o
        })
        .collect())
}

/// The oracle's rows of expressions on one batch of inputs.
fn oracle_rows(exprs: &[(E, Tol)], inputs: &[u32]) -> Result<Vec<Vec<Row>>, String> {
    let refs: Vec<&E> = exprs.iter().map(|x| &x.0).collect();
    oracle::expressions(&refs, &vec![0; refs.len()], &[inputs.to_vec()])
}

fn failing(o: &Outcome) -> bool {
    !matches!(o, Outcome::Agree { .. })
}

fn oracle_failing(o: &Outcome) -> bool {
    matches!(o, Outcome::OracleMismatch { .. } | Outcome::OracleError(_))
}

fn tol_for(x: &E, original: Tol) -> Tol {
    if run::uses_approx(x) {
        original
    } else {
        Tol::Exact
    }
}

/// Shrinks a failing expression: `fails` runs a batch of candidates and says which fail.
fn shrink(x: E, mut fails: impl FnMut(&[E]) -> Vec<bool>) -> E {
    let mut x = x;
    for _ in 0..64 {
        let cands: Vec<E> = shrink_candidates(&x).into_iter().take(48).collect();
        if cands.is_empty() {
            break;
        }
        let f = fails(&cands);
        match cands.into_iter().zip(f).find(|(_, f)| *f) {
            Some((c, _)) => x = c,
            None => break,
        }
    }
    x
}

/// The report of one failing expression from its outcome.
fn describe(x: &E, tol: Tol, inputs: &[u32], outcome: Result<&Outcome, String>) -> Failure {
    let host_rust = format!("host Rust: {}", super::host_text::expr(x));
    let (kind, detail) = match outcome {
        Err(e) => ("compile error", e),
        Ok(Outcome::Mismatch { row, gpu, host }) => (
            "mismatch",
            format!(
                "inputs: {}\ngpu:  {gpu}\nhost: {host}\ntolerance: {tol:?}",
                run::describe_row(inputs, *row)
            ),
        ),
        Ok(Outcome::OracleMismatch {
            row,
            gpu,
            oracle,
            host,
        }) => (
            "oracle mismatch",
            format!(
                "inputs: {}\ngpu:         {gpu}\ninterpreter: {host}\noracle:      {oracle}\n\
                 tolerance: {tol:?}\n{host_rust}",
                run::describe_row(inputs, *row)
            ),
        ),
        Ok(Outcome::HostError(e)) => ("host error", e.clone()),
        Ok(Outcome::OracleError(e)) => ("oracle error", format!("{e}\n{host_rust}")),
        Ok(Outcome::Agree { .. }) => ("mismatch", "no longer fails".into()),
    };
    Failure {
        kind,
        source: run::kernel_source(&[x]),
        expr: x.source(),
        detail,
    }
}

/// Runs a (shrunk) failing expression again and reports it, with the oracle when
/// `with_oracle`.
fn failure(gpu: &GpuContext, x: &E, tol: Tol, inputs: &[u32], with_oracle: bool) -> Failure {
    let one = [(x.clone(), tol)];
    let rows = if with_oracle {
        match oracle_rows(&one, inputs) {
            Ok(r) => Some(r),
            Err(e) => {
                let mut f = describe(x, tol, inputs, Err(e));
                f.kind = "oracle error";
                return f;
            }
        }
    } else {
        None
    };
    match run_batch(gpu, &one, inputs, rows.as_deref()) {
        Ok(o) => describe(x, tol, inputs, Ok(&o[0])),
        Err(e) => describe(x, tol, inputs, Err(e)),
    }
}

/// Shrinks a GPU-against-interpreter failure (or a compile error when `outcome` is `None`).
fn shrink_interp(gpu: &GpuContext, x: &E, tol: Tol, inputs: &[u32], compile_error: bool) -> E {
    shrink(x.clone(), |cands| {
        if compile_error {
            return cands.iter().map(|c| run::compile(&[c]).is_err()).collect();
        }
        let with_tol: Vec<(E, Tol)> = cands.iter().map(|c| (c.clone(), tol_for(c, tol))).collect();
        match run_batch(gpu, &with_tol, inputs, None) {
            Ok(o) => o.iter().map(failing).collect(),
            // A candidate that does not compile is not this failure.
            Err(_) => with_tol
                .iter()
                .map(|c| {
                    run_batch(gpu, std::slice::from_ref(c), inputs, None)
                        .is_ok_and(|o| failing(&o[0]))
                })
                .collect(),
        }
    })
}

/// Shrinks an oracle failure: each step compiles the candidates into one host program.
fn shrink_oracle(gpu: &GpuContext, x: &E, tol: Tol, inputs: &[u32]) -> E {
    shrink(x.clone(), |cands| {
        let with_tol: Vec<(E, Tol)> = cands.iter().map(|c| (c.clone(), tol_for(c, tol))).collect();
        let no = vec![false; cands.len()];
        let Ok(rows) = oracle_rows(&with_tol, inputs) else {
            return no;
        };
        match run_batch(gpu, &with_tol, inputs, Some(&rows)) {
            Ok(o) => o.iter().map(oracle_failing).collect(),
            Err(_) => no,
        }
    })
}

/// Runs `cfg.cases` expressions and shrinks every failure. `progress` is told after each batch.
pub fn fuzz(gpu: &GpuContext, cfg: &Config, mut progress: impl FnMut(&Report)) -> Report {
    let all = programs(cfg);
    let mut rng = Rng::new(cfg.seed ^ 0x1234_5678);
    let mut report = Report::default();
    let size = cfg.batch.max(1);
    let inputs: Vec<Vec<u32>> = all.chunks(size).map(|_| run::inputs(&mut rng)).collect();
    let oracle = if cfg.oracle {
        let refs: Vec<&E> = all.iter().map(|x| &x.0).collect();
        let batch: Vec<usize> = (0..all.len()).map(|k| k / size).collect();
        match oracle::expressions(&refs, &batch, &inputs) {
            Ok(rows) => Some(rows),
            Err(e) => {
                report.failures.push(Failure {
                    kind: "oracle error",
                    source: String::new(),
                    expr: String::new(),
                    detail: e,
                });
                None
            }
        }
    } else {
        None
    };
    let mut oracle_shrinks = 0;
    for (b, batch) in all.chunks(size).enumerate() {
        let inputs = &inputs[b];
        let rows = oracle
            .as_ref()
            .map(|o| &o[b * size..b * size + batch.len()]);
        report.expressions += batch.len();
        let outcomes: Vec<Option<Outcome>> = match run_batch(gpu, batch, inputs, rows) {
            Ok(o) => o.into_iter().map(Some).collect(),
            // Find the expressions that do not compile on their own.
            Err(_) => batch
                .iter()
                .enumerate()
                .map(|(k, x)| {
                    let rows = rows.map(|r| &r[k..=k]);
                    run_batch(gpu, std::slice::from_ref(x), inputs, rows)
                        .ok()
                        .map(|mut o| o.remove(0))
                })
                .collect(),
        };
        for ((x, tol), o) in batch.iter().zip(outcomes) {
            let f = match o {
                Some(Outcome::Agree {
                    compared,
                    skipped,
                    oracle,
                }) => {
                    report.rows_compared += compared;
                    report.rows_skipped += skipped;
                    report.oracle_rows += oracle;
                    continue;
                }
                Some(ref o) if oracle_failing(o) => {
                    if oracle_shrinks < ORACLE_SHRINKS {
                        oracle_shrinks += 1;
                        let small = shrink_oracle(gpu, x, *tol, inputs);
                        failure(gpu, &small, tol_for(&small, *tol), inputs, true)
                    } else {
                        describe(x, *tol, inputs, Ok(o))
                    }
                }
                o => {
                    let small = shrink_interp(gpu, x, *tol, inputs, o.is_none());
                    failure(gpu, &small, tol_for(&small, *tol), inputs, false)
                }
            };
            let key = |g: &Failure| -> String {
                let text = if matches!(g.kind, "compile error" | "oracle error") {
                    &g.detail
                } else {
                    &g.expr
                };
                text.chars()
                    .filter(|c| !c.is_ascii_digit())
                    .take(80)
                    .collect()
            };
            if !report.failures.iter().any(|g| key(g) == key(&f)) {
                report.failures.push(f);
            }
        }
        progress(&report);
    }
    report
}
