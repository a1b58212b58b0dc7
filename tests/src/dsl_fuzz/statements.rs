//! The differential test of statement programs: a batch of [`Program`]s is compiled into one
//! kernel (each program in its own block, its state stored to its own output words), run on
//! the GPU, and run again on the host by `codegen::interp::Machine` executing the whole
//! kernel (the `IN`/`OUT` buffers given as host values, one `main` call per row). Every output
//! word is compared exactly; failures are shrunk statement by statement.

use super::generate::Rng;
use super::program::{Program, program, shrink_candidates};
use super::run::{ROWS, describe_row, inputs, kernel_prelude, run_gpu};
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

/// Per program: `None` when its outputs agree on every row, else what differs.
fn run_batch(
    gpu: &GpuContext,
    progs: &[&Program],
    inputs: &[u32],
) -> Result<Vec<Option<String>>, String> {
    let src = kernel_source(progs);
    let c = codegen::compile_source(&src).map_err(|e| e.to_string())?;
    let wgsl = &c.variants.first().ok_or("no variant")?.wgsl;
    let stride = stride(progs);
    let gpu_out = run_gpu(gpu, wgsl, inputs, stride);
    let host_out = host(&c, inputs, stride).map_err(|e| format!("host: {e}"))?;
    let mut slot = 0;
    Ok(progs
        .iter()
        .map(|p| {
            let words = slot..slot + p.words();
            slot += p.words();
            (0..ROWS).find_map(|row| {
                let at = |out: &[u32]| out[row * stride..][words.clone()].to_vec();
                let (g, h) = (at(&gpu_out), at(&host_out));
                (g != h).then(|| {
                    format!(
                        "inputs: {}\ngpu words:  {g:?}\nhost words: {h:?}",
                        describe_row(inputs, row)
                    )
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
fn fails_alone(gpu: &GpuContext, p: &Program, inputs: &[u32]) -> Result<Option<String>, String> {
    run_batch(gpu, &[p], inputs).map(|mut r| r.remove(0))
}

/// Runs `cfg.cases` statement programs, shrinking every failure.
pub fn fuzz_programs(gpu: &GpuContext, cfg: &Config, mut progress: impl FnMut(&Report)) -> Report {
    let mut rng = Rng::new(cfg.seed ^ 0x57a7_e3e7);
    let all: Vec<Program> = (0..cfg.cases)
        .map(|i| program(&mut rng, i % 1000))
        .collect();
    let mut report = Report::default();
    // Programs are larger than expressions: a quarter of the expression batch per kernel.
    for batch in all.chunks((cfg.batch / 4).max(1)) {
        let inputs = inputs(&mut rng);
        report.expressions += batch.len();
        let refs: Vec<&Program> = batch.iter().collect();
        let outcomes: Vec<Result<Option<String>, String>> = match run_batch(gpu, &refs, &inputs) {
            Ok(o) => o.into_iter().map(Ok).collect(),
            Err(_) => batch.iter().map(|p| fails_alone(gpu, p, &inputs)).collect(),
        };
        for (p, o) in batch.iter().zip(outcomes) {
            match o {
                Ok(None) => report.rows_compared += ROWS,
                Ok(Some(_)) | Err(_) => {
                    let f = shrink_and_describe(gpu, p, &inputs);
                    if !report.failures.iter().any(|g| g.expr == f.expr) {
                        report.failures.push(f);
                    }
                }
            }
        }
        progress(&report);
    }
    report
}

/// What kind of failure `r` is (`None` for a pass): "mismatch", or the error message with
/// names and numbers blanked, so that shrinking keeps the same error.
fn kind_of(r: &Result<Option<String>, String>) -> Option<String> {
    match r {
        Ok(None) => None,
        Ok(Some(_)) => Some("mismatch".into()),
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

/// Shrinks a failing program to a smaller one that fails the same way.
fn shrink_and_describe(gpu: &GpuContext, p: &Program, inputs: &[u32]) -> Failure {
    let kind = kind_of(&fails_alone(gpu, p, inputs));
    let mut small = p.clone();
    for _ in 0..64 {
        let next = shrink_candidates(&small)
            .into_iter()
            .take(48)
            .find(|q| kind_of(&fails_alone(gpu, q, inputs)) == kind);
        match next {
            Some(q) => small = q,
            None => break,
        }
    }
    let r = fails_alone(gpu, &small, inputs);
    let kind = match &r {
        Ok(None) => "flaky",
        Ok(Some(_)) => "mismatch",
        Err(e) if e.starts_with("host:") => "host error",
        Err(_) => "compile error",
    };
    let detail = match r {
        Ok(Some(d)) | Err(d) => d,
        Ok(None) => "no longer fails".into(),
    };
    Failure {
        kind,
        source: kernel_source(&[&small]),
        expr: small.source(0, 0),
        detail,
    }
}
