//! Generated differential testing of DSL expressions: random well-typed expression trees over
//! `i32`, `u32`, `f32`, `bool` and their vectors are compiled through `codegen` (front end,
//! WGSL printer, naga validation, SPIR-V), run on the GPU over random inputs, and compared
//! with `codegen::interp` evaluating the IR of the same compiled module.
//!
//! - **Batches.** One kernel computes up to [`Config::batch`] expressions into separate output
//!   slots; 64 invocations give each expression 64 input rows (`i0..i3`, `u0..u3`, `f0..f3`,
//!   `b0..b3`, read from a storage buffer so nothing constant-folds).
//! - **Exactness.** Integers and bools compare exactly. Float operations that WGSL/Vulkan
//!   require correctly rounded (`+ - *`, negation, `abs floor ceil round fract trunc min max
//!   clamp saturate signum step`, `select`, constructors, swizzles, int→float casts) compare
//!   exactly (as values: `-0.0 == 0.0`), up to the driver's regrouping of float operations (a
//!   running error bound per node, see [`bound`]; `fuzz-dsl --strict` allows none). Approximate functions appear only at the root of an
//!   expression, on exact operands, with these tolerances (from the Vulkan precision table that
//!   WGSL defers to): `/` 3 ULP; `sqrt` 3 ULP; `inverse_sqrt` 2 ULP; `sin`/`cos` on
//!   [-3, 3] absolute 2^-11; `exp`/`exp2` on [-10, 10] 3 + 2·|x| ULP (33 ULP); `ln`/`log2`
//!   3 ULP or absolute 2^-21; `to_radians` 2 ULP; `length`, `normalize`, `distance` 8 ULP.
//!   Float `dot` and `mul_add` may round their products or not and sum in any order (WGSL
//!   gives both the accuracy of their expansion): their products count as intermediates of the
//!   regrouping allowance. Not generated: float `%` (`x - y * trunc(x / y)` inherits the
//!   division's error, which `trunc` can turn into a whole `y`), `powf`, `lerp`, `smoothstep`
//!   (error relative to intermediates the tree does not show), `from_bits` (NaN payloads).
//! - **Skipped rows.** A row where any float subexpression is NaN, infinite or subnormal is not
//!   compared (NaN-dependent results are indeterminate in WGSL; Vulkan may flush subnormals),
//!   nor one where a step (`floor`, a comparison, a float-to-int cast, ..) falls within the
//!   error bound of its float operand, or an approximate function's operand is not exact.
//! - **Shrinking.** A failing expression is shrunk greedily, type-aware: every subtree is
//!   replaced by a same-typed descendant or an input, all candidates run in one batch, and the
//!   smallest one that still fails is kept, until none does. (proptest's own shrinking of
//!   type-directed recursive strategies would need a strategy per type and depth; proptest
//!   drives the seeds instead.)

pub mod ast;
pub mod bound;
pub mod generate;
pub mod program;
pub mod run;
pub mod statements;

use ast::{E, T, Tol};
use generate::{GenConfig, Rng};
use proptest::strategy::{Strategy as _, ValueTree as _};
use proptest::test_runner::{Config as PtConfig, RngAlgorithm, TestRng, TestRunner};
use renderer::GpuContext;
use run::{Outcome, ROWS};

/// What to run.
#[derive(Debug, Clone, Copy)]
pub struct Config {
    /// The seed of the whole run.
    pub seed: u64,
    /// Number of expressions.
    pub cases: usize,
    /// Expressions per compiled kernel.
    pub batch: usize,
    /// Maximum expression depth.
    pub depth: u32,
    /// Generate unmasked shift amounts (see the guide's Semantics section).
    pub raw_shifts: bool,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            seed: 0x5eed,
            cases: 4096,
            batch: 48,
            depth: 4,
            raw_shifts: false,
        }
    }
}

/// One shrunk failure.
#[derive(Debug, Clone)]
pub struct Failure {
    /// What failed: "mismatch", "compile error" or "host error".
    pub kind: &'static str,
    /// The DSL source of the minimal failing program.
    pub source: String,
    /// The minimal expression.
    pub expr: String,
    /// The input row, the GPU value and the host value (or the error).
    pub detail: String,
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "{}: `{}`", self.kind, self.expr)?;
        writeln!(f, "{}", self.detail)?;
        write!(f, "program:\n{}", self.source)
    }
}

/// The result of a run.
#[derive(Debug, Clone, Default)]
pub struct Report {
    /// Cases generated: expressions, or statement programs.
    pub expressions: usize,
    /// Input rows compared.
    pub rows_compared: usize,
    /// Input rows skipped (non-finite or subnormal float subexpressions).
    pub rows_skipped: usize,
    /// Shrunk failures (duplicates after shrinking removed).
    pub failures: Vec<Failure>,
}

/// The expressions of a run: proptest draws one seed per expression from the run's seed.
pub fn programs(cfg: &Config) -> Vec<(E, Tol)> {
    let mut seed = [0u8; 32];
    seed[..8].copy_from_slice(&cfg.seed.to_le_bytes());
    let mut runner = TestRunner::new_with_rng(
        PtConfig::default(),
        TestRng::from_seed(RngAlgorithm::ChaCha, &seed),
    );
    let gc = GenConfig {
        depth: cfg.depth,
        raw_shifts: cfg.raw_shifts,
        floats: true,
    };
    let strategy = proptest::num::u64::ANY.prop_map(move |s| {
        let mut rng = Rng::new(s);
        let ty = generate::random_type(&mut rng);
        generate::expression(&mut rng, ty, gc)
    });
    (0..cfg.cases)
        .map(|_| strategy.new_tree(&mut runner).expect("a value").current())
        .collect()
}

/// Runs a batch: per expression, its outcome, or the compile error of the whole batch.
fn run_batch(gpu: &GpuContext, exprs: &[(E, Tol)], inputs: &[u32]) -> Result<Vec<Outcome>, String> {
    let refs: Vec<&E> = exprs.iter().map(|x| &x.0).collect();
    let c = run::compile(&refs)?;
    let stride: usize = refs.iter().map(|x| x.ty.n as usize).sum::<usize>().max(1);
    let out = run::run_gpu(gpu, &c.wgsl, inputs, stride);
    let mut slot = 0;
    Ok(exprs
        .iter()
        .enumerate()
        .map(|(k, (x, tol))| {
            let o = run::compare(&c, k, x.ty, *tol, inputs, &out, slot, stride);
            slot += x.ty.n as usize;
            o
        })
        .collect())
}

fn failing(o: &Outcome) -> bool {
    !matches!(o, Outcome::Agree { .. })
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
        let cands: Vec<E> = generate::shrink_candidates(&x)
            .into_iter()
            .take(48)
            .collect();
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

fn failure(gpu: &GpuContext, x: &E, tol: Tol, inputs: &[u32]) -> Failure {
    let source = run::kernel_source(&[x]);
    let detail = match run_batch(gpu, &[(x.clone(), tol)], inputs) {
        Err(e) => e,
        Ok(o) => match &o[0] {
            Outcome::Mismatch { row, gpu, host } => format!(
                "inputs: {}\ngpu:  {gpu}\nhost: {host}\ntolerance: {tol:?}",
                run::describe_row(inputs, *row)
            ),
            Outcome::HostError(e) => e.clone(),
            Outcome::Agree { .. } => "no longer fails".into(),
        },
    };
    let kind = match run_batch(gpu, &[(x.clone(), tol)], inputs) {
        Err(_) => "compile error",
        Ok(o) if matches!(o[0], Outcome::HostError(_)) => "host error",
        _ => "mismatch",
    };
    Failure {
        kind,
        source,
        expr: x.source(),
        detail,
    }
}

/// Runs `cfg.cases` expressions and shrinks every failure. `progress` is told after each batch.
pub fn fuzz(gpu: &GpuContext, cfg: &Config, mut progress: impl FnMut(&Report)) -> Report {
    let all = programs(cfg);
    let mut rng = Rng::new(cfg.seed ^ 0x1234_5678);
    let mut report = Report::default();
    for batch in all.chunks(cfg.batch.max(1)) {
        let inputs = run::inputs(&mut rng);
        report.expressions += batch.len();
        let outcomes: Vec<Option<Outcome>> = match run_batch(gpu, batch, &inputs) {
            Ok(o) => o.into_iter().map(Some).collect(),
            // Find the expressions that do not compile on their own.
            Err(_) => batch
                .iter()
                .map(|x| {
                    run_batch(gpu, std::slice::from_ref(x), &inputs)
                        .ok()
                        .map(|mut o| o.remove(0))
                })
                .collect(),
        };
        for ((x, tol), o) in batch.iter().zip(outcomes) {
            match o {
                Some(Outcome::Agree { compared, skipped }) => {
                    report.rows_compared += compared;
                    report.rows_skipped += skipped;
                }
                o => {
                    let compile_error = o.is_none();
                    let small = shrink(x.clone(), |cands| {
                        if compile_error {
                            return cands.iter().map(|c| run::compile(&[c]).is_err()).collect();
                        }
                        let with_tol: Vec<(E, Tol)> = cands
                            .iter()
                            .map(|c| (c.clone(), tol_for(c, *tol)))
                            .collect();
                        match run_batch(gpu, &with_tol, &inputs) {
                            Ok(o) => o.iter().map(failing).collect(),
                            // A candidate that does not compile is not this failure.
                            Err(_) => with_tol
                                .iter()
                                .map(|c| {
                                    run_batch(gpu, std::slice::from_ref(c), &inputs)
                                        .is_ok_and(|o| failing(&o[0]))
                                })
                                .collect(),
                        }
                    });
                    let f = failure(gpu, &small, tol_for(&small, *tol), &inputs);
                    let key = |g: &Failure| -> String {
                        let text = if g.kind == "compile error" {
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
            }
        }
        progress(&report);
    }
    report
}

/// Rows per expression (for reports).
pub const ROWS_PER_EXPRESSION: usize = ROWS;

/// The type of a generated expression (re-exported for tests).
pub fn type_of(x: &E) -> T {
    x.ty
}
