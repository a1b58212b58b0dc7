//! What `bench-codegen` measures, as plain data: the statistics of a sample, the figures of each
//! module, the incremental rebuilds, and the whole report.

/// The target for one variant (median), in milliseconds.
pub(super) const TARGET_MS_PER_VARIANT: f64 = 2.0;

/// Median, p90 and max of a sample, in the sample's unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Stats {
    pub samples: usize,
    pub median: f64,
    pub p90: f64,
    pub max: f64,
}

impl Stats {
    pub(super) fn of(values: &[f64]) -> Self {
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        Self {
            samples: sorted.len(),
            median: percentile(&sorted, 50.0),
            p90: percentile(&sorted, 90.0),
            max: percentile(&sorted, 100.0),
        }
    }
}

/// Figures of one `#[shader] mod`.
#[derive(Debug, Clone)]
pub(crate) struct ModuleFigures {
    pub name: String,
    /// Source file, relative to the workspace root.
    pub file: String,
    /// Keys of the axis matrix, excluded ones too.
    pub keys: usize,
    /// Distinct variants generated.
    pub variants: usize,
    pub wgsl_bytes: usize,
    pub spirv_bytes: usize,
    /// The variant with the most SPIR-V: (name, WGSL bytes, SPIR-V bytes).
    pub largest: (String, usize, usize),
    /// `codegen::compile`, median ms.
    pub compile_ms: f64,
    /// The shared part of it (front end, enumeration, duplicate keys), median ms.
    pub shared_ms: f64,
    /// `codegen::emit::emit`, median ms.
    pub emit_ms: f64,
}

/// Incremental builds of `shaders_gen`, in seconds.
#[derive(Debug, Clone)]
pub(crate) struct RebuildFigures {
    pub release: bool,
    /// The untimed build before the edits.
    pub warmup_s: f64,
    /// After the one-line kernel edit.
    pub edit_s: Vec<f64>,
    /// After a touch, tokens unchanged.
    pub touch_s: Vec<f64>,
}

/// Everything `bench-codegen` measures.
#[derive(Debug, Clone)]
pub(crate) struct Report {
    pub cpus: usize,
    pub cpu_model: Option<String>,
    pub rustc: Option<String>,
    /// 1-minute load average before and after the measurements (Linux): the machine is shared.
    pub load: (Option<f64>, Option<f64>),
    /// Whether xtask (the in-process compiler) is a debug build.
    pub debug: bool,
    pub iters: usize,
    /// Per variant, everything charged (`gen_time` + shared share), ms.
    pub per_variant: Stats,
    /// Per variant, `gen_time` only (what `cargo xtask shaders` prints), ms.
    pub per_variant_stages: Stats,
    pub modules: Vec<ModuleFigures>,
    /// Sum of every module's `codegen::compile`, median over the runs, ms.
    pub total_compile_ms: f64,
    /// Sum of every module's compile + emit, median over the runs, ms.
    pub total_expand_ms: f64,
    /// Compile + emit of the untimed warm-up run, ms.
    pub cold_expand_ms: f64,
    pub rebuild: Option<RebuildFigures>,
}

impl Report {
    pub(super) fn variants(&self) -> usize {
        self.modules.iter().map(|m| m.variants).sum()
    }
}

/// The `p`-th percentile (0 to 100) of sorted values, interpolated between the closest ranks;
/// NaN when empty.
pub(super) fn percentile(sorted: &[f64], p: f64) -> f64 {
    match sorted.len() {
        0 => f64::NAN,
        n => {
            let rank = (p / 100.0).clamp(0.0, 1.0) * (n - 1) as f64;
            let (lo, hi) = (rank.floor() as usize, rank.ceil() as usize);
            sorted[lo] + (sorted[hi] - sorted[lo]) * (rank - lo as f64)
        }
    }
}
