//! The host-Rust oracle: a second evaluation of the generated expressions and statement
//! programs that does not go through the DSL front end. Each case is printed as plain Rust
//! ([`super::host_text`]) over the guide's semantics ([`super::wgsl_rt`]), all cases of a run
//! are written into one Rust program (a function per case, `main` running every case on its
//! batch's input rows), compiled with `rustc` (debug, so that an overflow the runtime forgot
//! to wrap panics instead of wrapping by luck) and run; its output words are compared with the
//! GPU's, next to the interpreter's comparison.
//!
//! The sources are written under `target/dsl-oracle/` (`$CARGO_TARGET_DIR` if set) and kept
//! when `rustc` rejects them. Large runs are split over a few programs compiled in parallel.

use super::ast::E;
use super::host_text::{self, decode_inputs, host_type};
use super::inputs::{ROWS, WORDS};
use super::program::Program;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

/// One row's result of one case.
#[derive(Debug, Clone, PartialEq)]
pub enum Row {
    /// The output words.
    Words(Vec<u32>),
    /// A float value on the way was NaN, infinite or subnormal, or WGSL leaves the result
    /// open (a float `clamp` with `lo > hi`): not compared.
    Indeterminate,
    /// The host program panicked (an oracle bug: a runtime function left an overflow).
    Panicked(String),
}

/// A case: the body of a host function of the row's inputs that returns its output words.
#[derive(Debug, Clone)]
pub struct Case {
    /// Host Rust statements ending in a `Vec<u32>` expression.
    pub body: String,
    /// Which input rows it runs on (an index into the inputs given with it).
    pub batch: usize,
}

/// The case of an expression: its value's words.
pub fn expression_case(x: &E, batch: usize) -> Case {
    Case {
        body: format!(
            "    let r: {} = {};\n    words(r)\n",
            host_type(x.ty),
            host_text::expr(x)
        ),
        batch,
    }
}

/// The case of a statement program: its state's words.
pub fn program_case(p: &Program, batch: usize) -> Case {
    Case {
        body: host_text::program(p),
        batch,
    }
}

/// The oracle's results of expressions `exprs[k]` on `inputs[batch[k]]`: per case, per row.
pub fn expressions(
    exprs: &[&E],
    batch: &[usize],
    inputs: &[Vec<u32>],
) -> Result<Vec<Vec<Row>>, String> {
    let cases: Vec<Case> = exprs
        .iter()
        .zip(batch)
        .map(|(x, b)| expression_case(x, *b))
        .collect();
    evaluate(&cases, inputs)
}

/// The oracle's results of statement programs, as [`expressions`].
pub fn programs(
    progs: &[&Program],
    batch: &[usize],
    inputs: &[Vec<u32>],
) -> Result<Vec<Vec<Row>>, String> {
    let cases: Vec<Case> = progs
        .iter()
        .zip(batch)
        .map(|(p, b)| program_case(p, *b))
        .collect();
    evaluate(&cases, inputs)
}

/// Cases per compiled program: more are split over several `rustc` runs in parallel.
const CASES_PER_PROGRAM: usize = 800;

/// Runs every case on its rows: per case, [`ROWS`] results.
pub fn evaluate(cases: &[Case], inputs: &[Vec<u32>]) -> Result<Vec<Vec<Row>>, String> {
    if cases.is_empty() {
        return Ok(vec![]);
    }
    let chunks: Vec<&[Case]> = cases.chunks(CASES_PER_PROGRAM).collect();
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut out = Vec::with_capacity(cases.len());
    for group in chunks.chunks(threads) {
        let results: Vec<Result<Vec<Vec<Row>>, String>> = std::thread::scope(|s| {
            let handles: Vec<_> = group
                .iter()
                .map(|chunk| s.spawn(|| run_program(chunk, inputs)))
                .collect();
            handles
                .into_iter()
                .map(|h| {
                    h.join()
                        .unwrap_or_else(|_| Err("oracle thread panicked".into()))
                })
                .collect()
        });
        for r in results {
            out.extend(r?);
        }
    }
    Ok(out)
}

/// The host Rust program of `cases`: reads the input words from its first argument, writes
/// per case and row a flag (0 value, 1 indeterminate, 2 panicked), a length and the words.
pub fn program_source(cases: &[Case]) -> String {
    let mut s = String::from("#![allow(warnings)]\n\nmod wgsl_rt {\n");
    s.push_str(include_str!("wgsl_rt.rs"));
    s.push_str("}\n\nmod wgsl_rt_bits {\n");
    s.push_str(include_str!("wgsl_rt_bits.rs"));
    s.push_str("}\n\nmod wgsl_rt_float {\n");
    s.push_str(include_str!("wgsl_rt_float.rs"));
    s.push_str("}\n\nuse wgsl_rt::*;\nuse wgsl_rt_bits::*;\nuse wgsl_rt_float::*;\n\n");
    let decode = decode_inputs(super::ast::INPUTS_PER_TYPE);
    for (k, c) in cases.iter().enumerate() {
        let _ = writeln!(
            s,
            "fn case{k}(w: &[u32]) -> Vec<u32> {{\n{decode}{}}}\n",
            c.body
        );
    }
    s.push_str("const CASES: &[(fn(&[u32]) -> Vec<u32>, usize)] = &[\n");
    for (k, c) in cases.iter().enumerate() {
        let _ = writeln!(s, "    (case{k}, {}),", c.batch);
    }
    let _ = write!(
        s,
        r#"];

fn main() {{
    let args: Vec<String> = std::env::args().collect();
    let bytes = std::fs::read(&args[1]).expect("input words");
    let input: Vec<u32> = bytes.chunks(4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
    std::panic::set_hook(Box::new(|_| {{}}));
    let mut out: Vec<u32> = Vec::new();
    for (k, (f, batch)) in CASES.iter().enumerate() {{
        for row in 0..{ROWS} {{
            let w = &input[(batch * {ROWS} + row) * {WORDS}..][..{WORDS}];
            let _ = take_indeterminate();
            match std::panic::catch_unwind(|| f(w)) {{
                Ok(v) => {{
                    out.push(u32::from(take_indeterminate()));
                    out.push(v.len() as u32);
                    out.extend(v);
                }}
                Err(e) => {{
                    let msg = e.downcast_ref::<String>().cloned()
                        .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
                        .unwrap_or_default();
                    eprintln!("case {{k}} row {{row}}: {{msg}}");
                    out.push(2);
                    out.push(0);
                }}
            }}
        }}
    }}
    let bytes: Vec<u8> = out.iter().flat_map(|w| w.to_le_bytes()).collect();
    std::fs::write(&args[2], bytes).expect("output words");
}}
"#
    );
    s
}

fn work_dir() -> PathBuf {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target"));
    target.join("dsl-oracle")
}

static RUNS: AtomicUsize = AtomicUsize::new(0);

fn run_program(cases: &[Case], inputs: &[Vec<u32>]) -> Result<Vec<Vec<Row>>, String> {
    let dir = work_dir();
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let name = format!(
        "oracle-{}-{}",
        std::process::id(),
        RUNS.fetch_add(1, Ordering::Relaxed)
    );
    let src = dir.join(format!("{name}.rs"));
    let bin = dir.join(&name);
    let (input_file, output_file) = (
        dir.join(format!("{name}.in")),
        dir.join(format!("{name}.out")),
    );
    std::fs::write(&src, program_source(cases)).map_err(|e| e.to_string())?;
    let rustc = std::env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
    let compiled = Command::new(rustc)
        .args([
            "--edition",
            "2021",
            "-C",
            "opt-level=0",
            "-C",
            "debuginfo=0",
            "-o",
        ])
        .arg(&bin)
        .arg(&src)
        .output()
        .map_err(|e| format!("cannot run rustc: {e}"))?;
    if !compiled.status.success() {
        let err = String::from_utf8_lossy(&compiled.stderr);
        let head: String = err.lines().take(40).collect::<Vec<_>>().join("\n");
        return Err(format!(
            "the oracle program {} does not compile:\n{head}",
            src.display()
        ));
    }
    let bytes: Vec<u8> = inputs
        .iter()
        .flatten()
        .flat_map(|w| w.to_le_bytes())
        .collect();
    std::fs::write(&input_file, bytes).map_err(|e| e.to_string())?;
    let ran = Command::new(&bin)
        .arg(&input_file)
        .arg(&output_file)
        .output()
        .map_err(|e| format!("cannot run {}: {e}", bin.display()))?;
    if !ran.status.success() {
        return Err(format!(
            "the oracle program {} failed: {}",
            src.display(),
            String::from_utf8_lossy(&ran.stderr)
        ));
    }
    let words: Vec<u32> = std::fs::read(&output_file)
        .map_err(|e| e.to_string())?
        .chunks(4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    let panics = String::from_utf8_lossy(&ran.stderr).into_owned();
    for f in [&src, &bin, &input_file, &output_file] {
        let _ = std::fs::remove_file(f);
    }
    parse(&words, cases.len(), &panics)
}

fn parse(words: &[u32], cases: usize, panics: &str) -> Result<Vec<Vec<Row>>, String> {
    let mut at = 0;
    let mut next = || -> Result<u32, String> {
        let w = *words.get(at).ok_or("the oracle's output is short")?;
        at += 1;
        Ok(w)
    };
    let mut out = Vec::with_capacity(cases);
    for k in 0..cases {
        let mut rows = Vec::with_capacity(ROWS);
        for row in 0..ROWS {
            let flag = next()?;
            let len = next()?;
            let ws = (0..len)
                .map(|_| next())
                .collect::<Result<Vec<u32>, String>>()?;
            rows.push(match flag {
                0 => Row::Words(ws),
                1 => Row::Indeterminate,
                _ => {
                    let key = format!("case {k} row {row}: ");
                    let msg = panics
                        .lines()
                        .find_map(|l| l.strip_prefix(&key))
                        .unwrap_or("panicked");
                    Row::Panicked(msg.to_string())
                }
            });
        }
        out.push(rows);
    }
    Ok(out)
}
