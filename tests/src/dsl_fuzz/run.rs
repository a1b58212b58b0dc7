//! Compiles batches of generated expressions into one compute kernel, runs it on the GPU,
//! evaluates the same compiled IR on the host with `codegen::interp`, and compares; and
//! compares the GPU with the host-Rust oracle's rows ([`super::oracle`]) where given.

use super::ast::{E, INPUTS_PER_TYPE, Kind, Sc, T, Tol};
use super::bound::Bounds;
pub use super::inputs::{ROWS, WORDS, describe_row, inputs};
use super::oracle::Row;
use codegen::interp::{Value, eval_expr};
use codegen::ir::{Expr, ExprKind, Module, Stmt};
use renderer::{GpuContext, readback};
use std::fmt::Write as _;
use wgpu::util::DeviceExt as _;

/// The start of a fuzz kernel: the `IN`/`OUT` buffers and the input locals `i0..b3` of the
/// invocation's row, and `o`, its first output word (`stride` words per row).
pub fn kernel_prelude(stride: usize) -> String {
    let mut s = String::from(
        "#[shader]\nmod fuzz {\n    #[storage(group = 0, binding = 0)]\n    static IN: [u32];\n    #[storage(group = 0, binding = 1, read_write)]\n    static OUT: [u32];\n\n    #[compute(workgroup_size(64, 1, 1))]\n    fn main(#[builtin(global_invocation_id)] gid: UVec3) {\n",
    );
    let _ = writeln!(s, "        let base = gid.x * {WORDS}u32;");
    for (t, p) in ["i", "u", "f", "b"].iter().enumerate() {
        for i in 0..INPUTS_PER_TYPE {
            let w = t * INPUTS_PER_TYPE + i;
            let load = format!("IN[base + {w}u32]");
            let v = match *p {
                "i" => format!("{load} as i32"),
                "u" => load,
                "f" => format!("{load}.from_bits()"),
                _ => format!("{load} != 0u32"),
            };
            let _ = writeln!(s, "        let {p}{i} = {v};");
        }
    }
    let _ = writeln!(s, "        let o = gid.x * {stride}u32;");
    s
}

/// The DSL source of a kernel computing `exprs` into `OUT`.
pub fn kernel_source(exprs: &[&E]) -> String {
    let stride: usize = exprs.iter().map(|x| x.ty.n as usize).sum::<usize>().max(1);
    let mut s = kernel_prelude(stride);
    let mut slot = 0;
    for (k, x) in exprs.iter().enumerate() {
        let _ = writeln!(s, "        let r{k} = {};", x.source());
        for c in 0..x.ty.n {
            let comp = if x.ty.n == 1 {
                format!("r{k}")
            } else {
                format!("r{k}.{}", &"xyzw"[c as usize..c as usize + 1])
            };
            let store = match x.ty.s {
                Sc::F32 => format!("{comp}.to_bits()"),
                Sc::U32 => comp,
                _ => format!("{comp} as u32"),
            };
            let _ = writeln!(s, "        OUT[o + {slot}u32] = {store};");
            slot += 1;
        }
    }
    s.push_str("    }\n}\n");
    s
}

/// What went wrong with one expression.
#[derive(Debug, Clone)]
pub enum Outcome {
    /// The GPU and the host agree on every compared row.
    Agree {
        /// Rows compared.
        compared: usize,
        /// Rows skipped (a float subexpression was NaN, infinite or subnormal).
        skipped: usize,
        /// Rows also compared with the host-Rust oracle.
        oracle: usize,
    },
    /// They differ on `row`.
    Mismatch {
        /// The input row.
        row: usize,
        /// GPU value.
        gpu: Value,
        /// Host value.
        host: Value,
    },
    /// The GPU and the interpreter agree, but not with the host-Rust oracle on `row`.
    OracleMismatch {
        /// The input row.
        row: usize,
        /// GPU value.
        gpu: Value,
        /// The oracle's value.
        oracle: Value,
        /// The interpreter's value.
        host: Value,
    },
    /// The host evaluator failed.
    HostError(String),
    /// The oracle program panicked on a row.
    OracleError(String),
}

/// A compiled batch: WGSL, and each expression's IR.
pub struct Compiled {
    /// WGSL of the (single) variant.
    pub wgsl: String,
    module: Module,
    env: codegen::variants::Env,
    inputs: Vec<(usize, T, usize)>,
    results: Vec<Expr>,
    n_locals: usize,
}

impl std::fmt::Debug for Compiled {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Compiled").finish_non_exhaustive()
    }
}

/// Compiles a batch with `codegen` (front end, printer, naga validation, SPIR-V).
pub fn compile(exprs: &[&E]) -> Result<Compiled, String> {
    let src = kernel_source(exprs);
    let c = codegen::compile_source(&src).map_err(|e| e.to_string())?;
    let v = c.variants.first().ok_or("no variant")?;
    if v.spirv.is_empty() {
        return Err("no SPIR-V written".into());
    }
    let f = &c.module.functions[0];
    let mut inputs = vec![];
    let mut results = vec![None; exprs.len()];
    for st in &f.body {
        if let Stmt::Let {
            local: Some(l),
            init,
            ..
        } = st
        {
            let name = &f.locals[*l].name;
            let (p, rest) = name.split_at(1);
            let Ok(i) = rest.parse::<usize>() else {
                continue;
            };
            match p {
                "r" if i < exprs.len() => results[i] = Some(init.clone()),
                "i" | "u" | "f" | "b" => {
                    let t = "iufb".find(p).expect("prefix");
                    inputs.push((*l, T::scalar(Sc::ALL[t]), t * INPUTS_PER_TYPE + i));
                }
                _ => {}
            }
        }
    }
    let results = results
        .into_iter()
        .collect::<Option<Vec<_>>>()
        .ok_or("a result `let` is missing from the IR")?;
    Ok(Compiled {
        wgsl: v.wgsl.clone(),
        env: c.keys[0].env.clone(),
        n_locals: f.locals.len(),
        module: c.module,
        inputs,
        results,
    })
}

/// Runs a fuzz kernel's WGSL on the GPU over `inputs`, one row per invocation; the output
/// words (`stride` per row).
pub fn run_gpu(gpu: &GpuContext, wgsl: &str, inputs: &[u32], stride: usize) -> Vec<u32> {
    let d = gpu.device();
    let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("dsl fuzz"),
        source: wgpu::ShaderSource::Wgsl(wgsl.into()),
    });
    let pipeline = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("dsl fuzz"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let input = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("in"),
        contents: bytemuck::cast_slice(inputs),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let output = d.create_buffer(&wgpu::BufferDescriptor {
        label: Some("out"),
        size: (ROWS * stride.max(1) * 4) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: input.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: output.as_entire_binding(),
            },
        ],
    });
    let mut enc = d.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(1, 1, 1);
    }
    gpu.queue().submit([enc.finish()]);
    readback::read_buffer::<u32>(d, gpu.queue(), &output).expect("readback")
}

fn is_float(e: &Expr) -> bool {
    e.ty.scalar().is_some_and(|s| s.is_float())
}

fn sub_exprs<'a>(e: &'a Expr, out: &mut Vec<&'a Expr>) {
    out.push(e);
    match &e.kind {
        ExprKind::Unary(_, a)
        | ExprKind::Cast(a)
        | ExprKind::Swizzle(a, _)
        | ExprKind::Field(a, _) => sub_exprs(a, out),
        ExprKind::Binary(_, a, b) | ExprKind::Index(a, b) => {
            sub_exprs(a, out);
            sub_exprs(b, out);
        }
        ExprKind::Construct(args) | ExprKind::Builtin(_, args) | ExprKind::Call(_, args) => {
            for a in args {
                sub_exprs(a, out);
            }
        }
        _ => {}
    }
}

fn unruly(v: &Value) -> bool {
    v.components().iter().any(|c| match c {
        Value::F32(x) => !x.is_finite() || x.is_subnormal(),
        _ => false,
    })
}

fn ulps(a: f32, b: f32) -> u64 {
    let key = |x: f32| {
        let i = x.to_bits() as i32;
        (if i < 0 { i32::MIN.wrapping_sub(i) } else { i }) as i64
    };
    (key(a) - key(b)).unsigned_abs()
}

/// `fuzz-dsl --strict`: compare "exact" float results bit for bit, with no allowance for the
/// driver's reassociation.
pub static EXACT_SLACK_ULPS_STRICT: std::sync::atomic::AtomicBool =
    std::sync::atomic::AtomicBool::new(false);

fn strict() -> bool {
    EXACT_SLACK_ULPS_STRICT.load(std::sync::atomic::Ordering::Relaxed)
}

/// Whether a GPU component matches the host's under `tol`, allowing `regrouping` for the
/// driver's regrouping of float operations (see [`super::bound`]).
pub fn close(gpu: f32, host: f32, tol: Tol, regrouping: f32) -> bool {
    gpu == host
        || (gpu - host).abs() <= regrouping
        || match tol {
            Tol::Exact => false,
            Tol::Ulp(n) => ulps(gpu, host) <= n as u64,
            Tol::Abs(a) => (gpu - host).abs() <= a,
            Tol::UlpOrAbs(n, a) => ulps(gpu, host) <= n as u64 || (gpu - host).abs() <= a,
        }
}

impl Compiled {
    /// Host evaluation of result `k` on input row `row`; `None` when a float subexpression
    /// is NaN, infinite or subnormal there (not compared).
    pub fn host(
        &self,
        k: usize,
        inputs: &[u32],
        row: usize,
    ) -> Result<Option<(Value, f32)>, String> {
        let mut locals = vec![Value::Bool(false); self.n_locals];
        locals[0] = Value::Vector(vec![Value::U32(row as u32), Value::U32(0), Value::U32(0)]);
        for &(l, t, w) in &self.inputs {
            let bits = inputs[row * WORDS + w];
            locals[l] = match t.s {
                Sc::I32 => Value::I32(bits as i32),
                Sc::U32 => Value::U32(bits),
                Sc::F32 => Value::F32(f32::from_bits(bits)),
                Sc::Bool => Value::Bool(bits != 0),
            };
        }
        let root = &self.results[k];
        let mut subs = vec![];
        sub_exprs(root, &mut subs);
        for s in subs.iter().filter(|s| is_float(s)) {
            match eval_expr(&self.module, &self.env, s, &locals) {
                Ok(v) if unruly(&v) => return Ok(None),
                Ok(_) => {}
                Err(e) => return Err(e.to_string()),
            }
        }
        let regrouping = if strict() {
            0.0
        } else {
            let bounds = Bounds {
                module: &self.module,
                env: &self.env,
                locals: &locals,
            };
            match bounds.err(root)? {
                Some(err) => err,
                // The driver's regrouping may decide this row either way.
                None => return Ok(None),
            }
        };
        eval_expr(&self.module, &self.env, root, &locals)
            .map(|v| Some((v, regrouping)))
            .map_err(|e| e.to_string())
    }
}

/// Compares expression `k` (type `ty`, output words from `slot`) over every row with the
/// interpreter and, given its rows, the host-Rust oracle.
#[expect(
    clippy::too_many_arguments,
    reason = "one call site; the batch layout is plain data"
)]
pub fn compare(
    c: &Compiled,
    k: usize,
    ty: T,
    tol: Tol,
    inputs: &[u32],
    out: &[u32],
    slot: usize,
    stride: usize,
    oracle: Option<&[Row]>,
) -> Outcome {
    let (mut compared, mut skipped, mut oracle_rows) = (0, 0, 0);
    for row in 0..ROWS {
        let (host, regrouping) = match c.host(k, inputs, row) {
            Ok(Some(v)) => v,
            Ok(None) => {
                skipped += 1;
                continue;
            }
            Err(e) => return Outcome::HostError(e),
        };
        let gpu = values(
            ty,
            &out[row * stride + slot..row * stride + slot + ty.n as usize],
        );
        let agree = |reference: &Value| {
            let rc = reference.components();
            let gc = gpu.components();
            rc.len() == gc.len()
                && rc.iter().zip(&gc).all(|(r, g)| match (r, g) {
                    (Value::F32(r), Value::F32(g)) => close(*g, *r, tol, regrouping),
                    (r, g) => r == g,
                })
        };
        if !agree(&host) {
            return Outcome::Mismatch { row, gpu, host };
        }
        match oracle.map(|o| &o[row]) {
            Some(Row::Words(w)) => {
                let oracle = values(ty, w);
                oracle_rows += 1;
                if !agree(&oracle) {
                    return Outcome::OracleMismatch {
                        row,
                        gpu,
                        oracle,
                        host,
                    };
                }
            }
            Some(Row::Panicked(e)) => return Outcome::OracleError(format!("row {row}: {e}")),
            Some(Row::Indeterminate) | None => {}
        }
        compared += 1;
    }
    Outcome::Agree {
        compared,
        skipped,
        oracle: oracle_rows,
    }
}

/// A value of type `ty` from its output words (a scalar, or a vector of the lanes).
fn values(ty: T, words: &[u32]) -> Value {
    let lanes: Vec<Value> = words
        .iter()
        .map(|w| match ty.s {
            Sc::Bool => Value::Bool(*w != 0),
            s => Value::from_bits(codegen_scalar(s), *w),
        })
        .collect();
    if lanes.len() == 1 {
        lanes[0].clone()
    } else {
        Value::Vector(lanes)
    }
}

fn codegen_scalar(s: Sc) -> codegen::ir::Scalar {
    match s {
        Sc::I32 => codegen::ir::Scalar::I32,
        Sc::U32 => codegen::ir::Scalar::U32,
        Sc::F32 => codegen::ir::Scalar::F32,
        Sc::Bool => codegen::ir::Scalar::Bool,
    }
}

/// Whether an expression uses an approximate (tolerance-compared) float operation.
pub fn uses_approx(x: &E) -> bool {
    let here = match &x.kind {
        Kind::Bin("/", ..) => x.ty.s == Sc::F32,
        Kind::Method(m, ..) => matches!(
            *m,
            "sqrt"
                | "sin"
                | "cos"
                | "exp"
                | "exp2"
                | "ln"
                | "log2"
                | "inverse_sqrt"
                | "to_radians"
                | "length"
                | "normalize"
                | "distance"
        ),
        _ => false,
    };
    here || x.children().iter().any(|c| uses_approx(c))
}
