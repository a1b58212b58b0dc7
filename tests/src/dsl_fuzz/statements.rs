//! The differential test of statement programs: a batch of [`Program`]s is compiled into one
//! kernel (each program in its own block, its state stored to its own output words), run on
//! the GPU, and run again on the host by `codegen::interp::Machine` executing the whole
//! kernel (the `IN`/`OUT` buffers given as host values, one `main` call per row). Every output
//! word is compared exactly, and again with the host-Rust oracle's run of the same programs
//! ([`super::oracle`]); failures are shrunk statement by statement.

use super::generate::Rng;
use super::host_text;
use super::inputs::{ROWS, describe_row, inputs};
use super::oracle::{self, Row};
use super::program::{Program, program, shrink_candidates};
use super::run::{kernel_prelude, run_gpu};
use super::{Config, Failure, Report};
use codegen::interp::{Machine, Value};
use renderer::GpuContext;

/// The DSL source of a kernel running `progs`.
pub fn kernel_source(progs: &[&Program]) -> String {
    let stride = stride(progs);
    let mut s = kernel_prelude(stride);
    let mut slot = 0;
    for p in progs {
        s.push_str("        {\n");
        s.push_str(&p.source(slot, 12));
        s.push_str("        }\n");
        slot += p.words();
    }
    s.push_str("    }\n}\n");
    s
}

fn stride(progs: &[&Program]) -> usize {
    progs.iter().map(|p| p.words()).sum::<usize>().max(1)
}

/// What differs: "mismatch" (GPU against interpreter) or "oracle mismatch" (both against the
/// host-Rust oracle), and the words.
type Diff = Option<(&'static str, String)>;

/// Per program: `None` when its outputs agree on every row, else what differs. `oracle` has
/// the host-Rust oracle's rows of each program.
fn run_batch(
    gpu: &GpuContext,
    progs: &[&Program],
    inputs: &[u32],
    oracle: Option<&[Vec<Row>]>,
) -> Result<Vec<Diff>, String> {
    let src = kernel_source(progs);
    let c = codegen::compile_source(&src).map_err(|e| e.to_string())?;
    let wgsl = &c.variants.first().ok_or("no variant")?.wgsl;
    let stride = stride(progs);
    let gpu_out = run_gpu(gpu, wgsl, inputs, stride);
    let host_out = host(&c, inputs, stride).map_err(|e| format!("host: {e}"))?;
    let mut slot = 0;
    Ok(progs
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let words = slot..slot + p.words();
            slot += p.words();
            (0..ROWS).find_map(|row| {
                let at = |out: &[u32]| out[row * stride..][words.clone()].to_vec();
                let (g, h) = (at(&gpu_out), at(&host_out));
                let row_text = describe_row(inputs, row);
                if g != h {
                    let d = format!("inputs: {row_text}\ngpu words:  {g:?}\nhost words: {h:?}");
                    return Some(("mismatch", d));
                }
                let o = match oracle.map(|o| &o[k][row]) {
                    Some(Row::Words(o)) => o,
                    Some(Row::Panicked(e)) => return Some(("oracle error", e.clone())),
                    Some(Row::Indeterminate) | None => return None,
                };
                (*o != g).then(|| {
                    let d = format!(
                        "inputs: {row_text}\ngpu words:         {g:?}\ninterpreter words: \
                         {h:?}\noracle words:      {o:?}"
                    );
                    ("oracle mismatch", d)
                })
            })
        })
        .collect())
}

/// The kernel run on the host: `main` once per row.
fn host(c: &codegen::Compiled, inputs: &[u32], stride: usize) -> Result<Vec<u32>, String> {
    let mut m = Machine::new(&c.module, &c.keys[0].env);
    let words = |w: &[u32]| Value::Array(w.iter().map(|&x| Value::U32(x)).collect());
    m.set_global("IN", words(inputs))
        .map_err(|e| e.to_string())?;
    m.set_global("OUT", words(&vec![0; ROWS * stride]))
        .map_err(|e| e.to_string())?;
    for row in 0..ROWS {
        let gid = Value::Vector(vec![Value::U32(row as u32), Value::U32(0), Value::U32(0)]);
        m.run("main", vec![gid]).map_err(|e| e.to_string())?;
    }
    match m.global_value("OUT") {
        Some(Value::Array(items)) => Ok(items.iter().filter_map(Value::bits).collect()),
        _ => Err("OUT lost its value".into()),
    }
}

/// Per program: whether it fails (compile error, host error or mismatch) on its own.
fn fails_alone(
    gpu: &GpuContext,
    p: &Program,
    inputs: &[u32],
    oracle: Option<&[Row]>,
) -> Result<Diff, String> {
    let rows = oracle.map(|r| vec![r.to_vec()]);
    run_batch(gpu, &[p], inputs, rows.as_deref()).map(|mut r| r.remove(0))
}

/// The oracle's rows of programs on one batch of inputs.
fn oracle_rows(progs: &[&Program], inputs: &[u32]) -> Result<Vec<Vec<Row>>, String> {
    oracle::programs(progs, &vec![0; progs.len()], &[inputs.to_vec()])
}

/// Oracle failures shrunk per run; later ones are reported as found.
const ORACLE_SHRINKS: usize = 3;

/// Runs `cfg.cases` statement programs, shrinking every failure.
pub fn fuzz_programs(gpu: &GpuContext, cfg: &Config, mut progress: impl FnMut(&Report)) -> Report {
    let mut rng = Rng::new(cfg.seed ^ 0x57a7_e3e7);
    let all: Vec<Program> = (0..cfg.cases)
        .map(|i| program(&mut rng, i % 1000))
        .collect();
    let mut report = Report::default();
    // Programs are larger than expressions: a quarter of the expression batch per kernel.
    let size = (cfg.batch / 4).max(1);
    let inputs: Vec<Vec<u32>> = all.chunks(size).map(|_| inputs(&mut rng)).collect();
    let oracle = if cfg.oracle {
        let refs: Vec<&Program> = all.iter().collect();
        let batch: Vec<usize> = (0..all.len()).map(|k| k / size).collect();
        match oracle::programs(&refs, &batch, &inputs) {
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
        let refs: Vec<&Program> = batch.iter().collect();
        let outcomes: Vec<Result<Diff, String>> = match run_batch(gpu, &refs, inputs, rows) {
            Ok(o) => o.into_iter().map(Ok).collect(),
            Err(_) => batch
                .iter()
                .enumerate()
                .map(|(k, p)| fails_alone(gpu, p, inputs, rows.map(|r| r[k].as_slice())))
                .collect(),
        };
        for (k, (p, o)) in batch.iter().zip(outcomes).enumerate() {
            let f = match o {
                Ok(None) => {
                    report.rows_compared += ROWS;
                    if rows.is_some() {
                        report.oracle_rows += ROWS;
                    }
                    continue;
                }
                Ok(Some((kind, d))) if kind.starts_with("oracle") => {
                    if oracle_shrinks < ORACLE_SHRINKS {
                        oracle_shrinks += 1;
                        shrink_and_describe(gpu, p, inputs, true)
                    } else {
                        let _ = k;
                        Failure {
                            kind,
                            source: kernel_source(&[p]),
                            expr: p.source(0, 0),
                            detail: format!("{d}\nhost Rust:\n{}", host_text::program(p)),
                        }
                    }
                }
                Ok(Some(_)) | Err(_) => shrink_and_describe(gpu, p, inputs, false),
            };
            if !report.failures.iter().any(|g| g.expr == f.expr) {
                report.failures.push(f);
            }
        }
        progress(&report);
    }
    report
}

/// What kind of failure `r` is (`None` for a pass): "mismatch", "oracle mismatch", or the
/// error message with names and numbers blanked, so that shrinking keeps the same error.
fn kind_of(r: &Result<Diff, String>) -> Option<String> {
    match r {
        Ok(None) => None,
        Ok(Some((kind, _))) => Some((*kind).into()),
        Err(e) => Some(
            e.lines()
                .next()
                .unwrap_or_default()
                .split('`')
                .step_by(2)
                .collect::<String>()
                .chars()
                .filter(|c| !c.is_ascii_digit())
                .collect(),
        ),
    }
}

/// Shrinks a failing program to a smaller one that fails the same way; with the oracle, each
/// step compiles the candidates into one host program.
fn shrink_and_describe(
    gpu: &GpuContext,
    p: &Program,
    inputs: &[u32],
    with_oracle: bool,
) -> Failure {
    let alone = |q: &Program, rows: Option<&[Row]>| fails_alone(gpu, q, inputs, rows);
    let rows_of = |qs: &[&Program]| -> Option<Vec<Vec<Row>>> {
        if with_oracle {
            oracle_rows(qs, inputs).ok()
        } else {
            None
        }
    };
    let first = rows_of(&[p]);
    let kind = kind_of(&alone(p, first.as_ref().map(|r| r[0].as_slice())));
    let mut small = p.clone();
    for _ in 0..64 {
        let mut cands: Vec<Program> = shrink_candidates(&small).into_iter().take(48).collect();
        if with_oracle {
            // A candidate that reads a removed loop's variable is no program: it would fail the
            // whole host program's compilation, and cannot fail the same way.
            cands.retain(|q| codegen::compile_source(&kernel_source(&[q])).is_ok());
        }
        let refs: Vec<&Program> = cands.iter().collect();
        let rows = rows_of(&refs);
        if with_oracle && rows.is_none() {
            break;
        }
        // Mismatches: all candidates in one kernel (each program is its own block).
        let together = kind
            .as_deref()
            .filter(|k| k.ends_with("mismatch"))
            .and_then(|_| run_batch(gpu, &refs, inputs, rows.as_deref()).ok());
        let next = cands.iter().enumerate().find(|(i, q)| match &together {
            Some(diffs) => diffs[*i].as_ref().map(|d| d.0) == kind.as_deref(),
            None => kind_of(&alone(q, rows.as_ref().map(|r| r[*i].as_slice()))) == kind,
        });
        match next {
            Some((_, q)) => small = q.clone(),
            None => break,
        }
    }
    let rows = rows_of(&[&small]);
    let r = alone(&small, rows.as_ref().map(|r| r[0].as_slice()));
    let kind = match &r {
        Ok(None) => "flaky",
        Ok(Some((kind, _))) => kind,
        Err(e) if e.starts_with("host:") => "host error",
        Err(_) => "compile error",
    };
    let mut detail = match r {
        Ok(Some((_, d))) | Err(d) => d,
        Ok(None) => "no longer fails".into(),
    };
    if with_oracle {
        detail.push_str(&format!("\nhost Rust:\n{}", host_text::program(&small)));
    }
    Failure {
        kind,
        source: kernel_source(&[&small]),
        expr: small.source(0, 0),
        detail,
    }
}
