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
//! - **A second oracle.** The interpreter evaluates the IR of the DSL front end, so a bug in
//!   lowering Rust to IR would be on both sides. The same expressions (and statement programs)
//!   are also printed as plain host Rust over the guide's semantics ([`wgsl_rt`],
//!   [`host_text`]), compiled with `rustc` and run ([`oracle`]); the GPU must match it too,
//!   with the same tolerance per row (rows where the oracle meets NaN, infinity, a subnormal
//!   or a float `clamp` with `lo > hi` are not compared with it).
//! - **Shrinking.** A failing expression is shrunk greedily, type-aware: every subtree is
//!   replaced by a same-typed descendant or an input, all candidates run in one batch, and the
//!   smallest one that still fails is kept, until none does. (proptest's own shrinking of
//!   type-directed recursive strategies would need a strategy per type and depth; proptest
//!   drives the seeds instead.)

pub mod ast;
pub mod bound;
pub mod expressions;
pub mod generate;
pub mod host_text;
pub mod inputs;
pub mod oracle;
pub mod program;
pub mod program_gen;
pub mod program_text;
pub mod rng;
pub mod run;
pub mod shrink;
pub mod statements;
pub mod wgsl_rt;
pub mod wgsl_rt_bits;
pub mod wgsl_rt_float;

use ast::{E, T, Tol};
pub use expressions::fuzz;
use generate::{GenConfig, Rng};
use inputs::ROWS;
use proptest::strategy::{Strategy as _, ValueTree as _};
use proptest::test_runner::{Config as PtConfig, RngAlgorithm, TestRng, TestRunner};

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
    /// Also compare the GPU with the host-Rust oracle ([`oracle`]).
    pub oracle: bool,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            seed: 0x5eed,
            cases: 4096,
            batch: 48,
            depth: 4,
            raw_shifts: false,
            oracle: true,
        }
    }
}

/// One shrunk failure.
#[derive(Debug, Clone)]
pub struct Failure {
    /// What failed: "mismatch" (GPU against interpreter), "oracle mismatch" (GPU and
    /// interpreter against the host-Rust oracle), "compile error", "host error" or
    /// "oracle error".
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
    /// Input rows also compared with the host-Rust oracle.
    pub oracle_rows: usize,
    /// Failures (duplicates after shrinking removed); oracle failures past the first few
    /// are kept unshrunk (each shrinking step compiles a host program).
    pub failures: Vec<Failure>,
}

impl Report {
    /// The failures as text: the first `n` in full, then how many more.
    pub fn failures_text(&self, n: usize) -> String {
        let mut text: Vec<String> = self
            .failures
            .iter()
            .take(n)
            .map(|f| f.to_string())
            .collect();
        if self.failures.len() > n {
            text.push(format!("... and {} more failures", self.failures.len() - n));
        }
        text.join("\n\n")
    }
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

/// Rows per expression (for reports).
pub const ROWS_PER_EXPRESSION: usize = ROWS;

/// The type of a generated expression (re-exported for tests).
pub fn type_of(x: &E) -> T {
    x.ty
}
