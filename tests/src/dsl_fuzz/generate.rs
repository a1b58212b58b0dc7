//! Random well-typed expressions: type-directed generation from a seed ([`Rng`]); the
//! candidates a failing expression shrinks to are in [`super::shrink`].

use super::ast::{E, INPUTS_PER_TYPE, Kind, Sc, T, Tol};
pub use super::rng::Rng;
pub use super::shrink::shrink_candidates;

fn e(ty: T, kind: Kind) -> E {
    E { ty, kind }
}

fn b(x: E) -> Box<E> {
    Box::new(x)
}

/// An input local of scalar type `s`, or a splat of one for a vector.
pub fn input(rng: &mut Rng, ty: T) -> E {
    let leaf = e(T::scalar(ty.s), Kind::Input(rng.below(INPUTS_PER_TYPE)));
    if ty.n == 1 {
        leaf
    } else {
        e(ty, Kind::Splat(b(leaf)))
    }
}

fn literal(rng: &mut Rng, s: Sc) -> E {
    let text = match s {
        Sc::I32 => format!(
            "{}i32",
            rng.pick(&[0, 1, 2, 3, 7, 31, 32, 100, 65535, 2147483647])
        ),
        Sc::U32 => format!(
            "{}u32",
            rng.pick(&[0u32, 1, 2, 5, 31, 32, 33, 255, 65536, 4294967295])
        ),
        Sc::F32 => rng
            .pick(&["0.0", "1.0", "0.5", "2.0", "3.0", "0.25", "100.0", "1.5"])
            .to_string(),
        Sc::Bool => rng.pick(&["true", "false"]).to_string(),
    };
    e(T::scalar(s), Kind::Lit(text))
}

fn leaf(rng: &mut Rng, ty: T) -> E {
    if ty.n == 1 && rng.chance(25) {
        literal(rng, ty.s)
    } else {
        input(rng, ty)
    }
}

/// Whether a divisor may have a lane naga sees as a constant (a literal reached through
/// constructors, splats and swizzles): a constant zero lane is a compile error, so divisors with
/// any constant lane are replaced.
pub fn has_constant_lane(x: &E) -> bool {
    match &x.kind {
        Kind::Lit(_) => true,
        Kind::Input(_) | Kind::Var(_) => false,
        Kind::New(parts) => parts.iter().any(has_constant_lane),
        Kind::Splat(a) | Kind::Swizzle(a, _) | Kind::AsVec(a) => has_constant_lane(a),
        _ => !x.has_input(),
    }
}

/// Generation settings.
#[derive(Debug, Clone, Copy)]
pub struct GenConfig {
    /// Maximum nesting depth.
    pub depth: u32,
    /// Allow shift amounts that are not masked to `0..32` (WGSL defines them modulo 32).
    pub raw_shifts: bool,
    /// Let integer and `bool` expressions read floats (casts, comparisons, conversions).
    /// Statement programs turn this off: a float comparison within the driver's regrouping
    /// error could take the other branch, and their state has no error bound.
    pub floats: bool,
}

impl GenConfig {
    /// The numeric types an integer or `bool` expression may convert or compare from.
    fn numeric_sources(self) -> &'static [Sc] {
        if self.floats {
            &[Sc::I32, Sc::U32, Sc::F32]
        } else {
            &[Sc::I32, Sc::U32]
        }
    }
}

/// Generates an expression of type `ty` and the tolerance its float components are compared
/// with. Approximate float functions (`/`, `sqrt`, `sin`, ..) occur only at the root, with
/// exactly-rounded operands, so that the stated per-builtin tolerance is the whole error.
pub fn expression(rng: &mut Rng, ty: T, cfg: GenConfig) -> (E, Tol) {
    if ty.s == Sc::F32 && rng.chance(30) {
        let (x, tol) = approx_root(rng, ty, cfg);
        return (x, tol);
    }
    (rgen(rng, ty, cfg.depth, cfg), Tol::Exact)
}

/// A random output type.
pub fn random_type(rng: &mut Rng) -> T {
    let s = *rng.pick(&Sc::ALL);
    let n = if rng.chance(50) {
        1
    } else {
        2 + rng.below(3) as u8
    };
    T { n, s }
}

fn float_like(rng: &mut Rng, n: u8, cfg: GenConfig) -> E {
    rgen(rng, T { n, s: Sc::F32 }, cfg.depth.saturating_sub(1), cfg)
}

fn m(ty: T, name: &'static str, recv: E, args: Vec<E>) -> E {
    e(ty, Kind::Method(name, b(recv), args))
}

/// A float literal, splat to `n` components (vector methods take vector arguments).
fn flit_n(x: &str, n: u8) -> E {
    let l = e(T::scalar(Sc::F32), Kind::Lit(x.into()));
    if n == 1 {
        l
    } else {
        e(T { n, s: Sc::F32 }, Kind::Splat(b(l)))
    }
}

fn approx_root(rng: &mut Rng, ty: T, cfg: GenConfig) -> (E, Tol) {
    let n = ty.n;
    let flit = |x: &str| flit_n(x, n);
    let x = || T { n, s: Sc::F32 };
    let mut a = float_like(rng, n, cfg);
    // A constant operand would make the whole root constant (`0.5 / 0.0` is a compile error).
    if !a.has_input() {
        a = input(rng, a.ty);
    }
    let k = rng.below(if n == 1 { 10 } else { 13 });
    match k {
        0 => {
            let d = float_like(rng, n, cfg);
            (e(ty, Kind::Bin("/", b(a), b(d))), Tol::Ulp(3))
        }
        1 => (m(ty, "sqrt", m(x(), "abs", a, vec![]), vec![]), Tol::Ulp(3)),
        2 | 3 => {
            let name = if k == 2 { "sin" } else { "cos" };
            let c = m(x(), "clamp", a, vec![flit("-3.0"), flit("3.0")]);
            (m(ty, name, c, vec![]), Tol::Abs(1.0 / 2048.0))
        }
        4 | 5 => {
            let name = if k == 4 { "exp" } else { "exp2" };
            let c = m(x(), "clamp", a, vec![flit("-10.0"), flit("10.0")]);
            (m(ty, name, c, vec![]), Tol::Ulp(3 + 2 * 15))
        }
        6 | 7 => {
            let name = if k == 6 { "ln" } else { "log2" };
            let pos = e(
                x(),
                Kind::Bin("+", b(m(x(), "abs", a, vec![])), b(flit("0.5"))),
            );
            (
                m(ty, name, pos, vec![]),
                Tol::UlpOrAbs(3, 1.0 / 2_097_152.0),
            )
        }
        8 => {
            let pos = e(
                x(),
                Kind::Bin("+", b(m(x(), "abs", a, vec![])), b(flit("1.0"))),
            );
            (m(ty, "inverse_sqrt", pos, vec![]), Tol::Ulp(2))
        }
        9 => {
            a = m(x(), "clamp", a, vec![flit("-1000.0"), flit("1000.0")]);
            (m(ty, "to_radians", a, vec![]), Tol::Ulp(2))
        }
        10 => (m(T::scalar(Sc::F32), "length", a, vec![]), Tol::Ulp(8)).pipe_vec(rng, ty),
        11 => (m(ty, "normalize", a, vec![]), Tol::Ulp(8)),
        _ => {
            let w = float_like(rng, n, cfg);
            (m(T::scalar(Sc::F32), "distance", a, vec![w]), Tol::Ulp(8)).pipe_vec(rng, ty)
        }
    }
}

trait PipeVec {
    fn pipe_vec(self, rng: &mut Rng, ty: T) -> (E, Tol);
}

impl PipeVec for (E, Tol) {
    /// A scalar result where a vector was asked for: splat it.
    fn pipe_vec(self, _rng: &mut Rng, ty: T) -> (E, Tol) {
        if ty.n == 1 {
            self
        } else {
            (e(ty, Kind::Splat(b(self.0))), self.1)
        }
    }
}

/// An exactly-computable expression of type `ty`.
pub fn rgen(rng: &mut Rng, ty: T, depth: u32, cfg: GenConfig) -> E {
    if depth == 0 || rng.chance(15) {
        return leaf(rng, ty);
    }
    let d = depth - 1;
    let mut x = if ty.n > 1 {
        vector(rng, ty, d, cfg)
    } else {
        scalar(rng, ty.s, d, cfg)
    };
    // A tree without an input is a constant expression: naga folds it and rejects overflow.
    if !x.has_input()
        && let Some(c) = x.children_mut().into_iter().next()
    {
        *c = input(rng, c.ty);
    }
    x
}

fn any_vec(rng: &mut Rng, s: Sc) -> T {
    T {
        n: 2 + rng.below(3) as u8,
        s,
    }
}

/// Swizzle, index or component of a random vector, giving type `ty`.
fn from_vector(rng: &mut Rng, ty: T, d: u32, cfg: GenConfig) -> E {
    let src = if ty.n == 1 {
        any_vec(rng, ty.s)
    } else {
        T {
            n: 2 + rng.below(3) as u8,
            s: ty.s,
        }
    };
    let v = rgen(rng, src, d, cfg);
    if ty.n == 1 && rng.chance(40) {
        let i = rgen(rng, T::scalar(Sc::U32), d, cfg);
        return e(ty, Kind::Index(b(v), b(i)));
    }
    let comps = &"xyzw"[..src.n as usize];
    let sw: String = (0..ty.n)
        .map(|_| comps.as_bytes()[rng.below(comps.len())] as char)
        .collect();
    e(ty, Kind::Swizzle(b(v), sw))
}

fn vector(rng: &mut Rng, ty: T, d: u32, cfg: GenConfig) -> E {
    let s = ty.s;
    let numeric = s != Sc::Bool;
    match rng.below(10) {
        0 => e(ty, Kind::Splat(b(rgen(rng, T::scalar(s), d, cfg)))),
        1 | 2 => {
            // Components, some of them sub-vectors.
            let mut parts = vec![];
            let mut left = ty.n;
            while left > 0 {
                let k = if left >= 2 && rng.chance(30) { 2 } else { 1 };
                parts.push(rgen(rng, T { n: k, s }, d, cfg));
                left -= k;
            }
            e(ty, Kind::New(parts))
        }
        3 => from_vector(rng, ty, d, cfg),
        4 => {
            let c = rgen(rng, T::scalar(Sc::Bool), d, cfg);
            e(
                ty,
                Kind::Select(b(c), b(rgen(rng, ty, d, cfg)), b(rgen(rng, ty, d, cfg))),
            )
        }
        5 if numeric => {
            let from = *rng.pick(cfg.numeric_sources());
            e(
                ty,
                Kind::AsVec(b(rgen(rng, T { n: ty.n, s: from }, d, cfg))),
            )
        }
        _ if numeric => numeric_op(rng, ty, d, cfg),
        _ => e(ty, Kind::Splat(b(rgen(rng, T::scalar(s), d, cfg)))),
    }
}

/// Arithmetic, bit operations and math methods on a numeric scalar or vector type.
fn numeric_op(rng: &mut Rng, ty: T, d: u32, cfg: GenConfig) -> E {
    let s = ty.s;
    let g = |rng: &mut Rng| rgen(rng, ty, d, cfg);
    let scalar_side = |rng: &mut Rng| rgen(rng, T::scalar(s), d, cfg);
    let int = s != Sc::F32;
    let ops: &[&str] = if int {
        &[
            "+", "-", "*", "/", "%", "&", "|", "^", "<<", ">>", "min", "max", "clamp", "abs", "!",
            "neg", "bits",
        ]
    } else {
        &[
            "+", "-", "*", "min", "max", "clamp", "abs", "neg", "floor", "ceil", "round", "fract",
            "trunc", "saturate", "signum", "step", "mul_add",
        ]
    };
    let op = *rng.pick(ops);
    match op {
        "+" | "-" | "*" | "/" | "%" | "&" | "|" | "^" => {
            let a = g(rng);
            // Vector-scalar forms for arithmetic.
            let rhs = if ty.n > 1 && rng.chance(20) && matches!(op, "+" | "-" | "*") {
                scalar_side(rng)
            } else {
                g(rng)
            };
            // A constant zero divisor, or a vector divisor with a constant zero component, is a
            // compile error (naga; see the guide).
            let rhs = if matches!(op, "/" | "%") && has_constant_lane(&rhs) {
                input(rng, rhs.ty)
            } else {
                rhs
            };
            e(ty, Kind::Bin(op, b(a), b(rhs)))
        }
        "<<" | ">>" => {
            let a = g(rng);
            let amount_ty = T {
                n: ty.n,
                s: *rng.pick(&[Sc::U32, Sc::I32]),
            };
            let mut amt = rgen(rng, amount_ty, d, cfg);
            if !amt.has_input() {
                amt = input(rng, amount_ty);
            }
            if !cfg.raw_shifts {
                let mask = e(
                    T::scalar(amount_ty.s),
                    Kind::Lit(format!("31{}", amount_ty.s.name())),
                );
                let mask = if ty.n > 1 {
                    e(amount_ty, Kind::Splat(b(mask)))
                } else {
                    mask
                };
                amt = e(amount_ty, Kind::Bin("&", b(amt), b(mask)));
            }
            e(ty, Kind::Bin(op, b(a), b(amt)))
        }
        "min" | "max" | "step" => m(ty, op, g(rng), vec![g(rng)]),
        "clamp" | "mul_add" => m(ty, op, g(rng), vec![g(rng), g(rng)]),
        "neg" if s == Sc::U32 => e(ty, Kind::Un("!", b(g(rng)))),
        "neg" => e(ty, Kind::Un("-", b(g(rng)))),
        "!" => e(ty, Kind::Un("!", b(g(rng)))),
        "bits" => {
            let name = *rng.pick(&[
                "count_ones",
                "leading_zeros",
                "trailing_zeros",
                "reverse_bits",
            ]);
            m(ty, name, g(rng), vec![])
        }
        other => m(ty, other, g(rng), vec![]),
    }
}

fn scalar(rng: &mut Rng, s: Sc, d: u32, cfg: GenConfig) -> E {
    let ty = T::scalar(s);
    let k = rng.below(10);
    if k == 0 {
        return from_vector(rng, ty, d, cfg);
    }
    if k == 1 {
        let c = rgen(rng, T::scalar(Sc::Bool), d, cfg);
        return e(
            ty,
            Kind::Select(b(c), b(rgen(rng, ty, d, cfg)), b(rgen(rng, ty, d, cfg))),
        );
    }
    match s {
        Sc::Bool => match rng.below(5) {
            0 | 1 => {
                let cs = *rng.pick(cfg.numeric_sources());
                let op = *rng.pick(&["==", "!=", "<", "<=", ">", ">="]);
                let a = rgen(rng, T::scalar(cs), d, cfg);
                let c = rgen(rng, T::scalar(cs), d, cfg);
                e(ty, Kind::Bin(op, b(a), b(c)))
            }
            2 => e(ty, Kind::Un("!", b(rgen(rng, ty, d, cfg)))),
            _ => {
                let op = *rng.pick(&["&&", "||", "==", "!=", "&", "|", "^"]);
                e(
                    ty,
                    Kind::Bin(op, b(rgen(rng, ty, d, cfg)), b(rgen(rng, ty, d, cfg))),
                )
            }
        },
        _ => {
            if k == 2 {
                // Casts between the numeric types, and from bool to integers.
                let from = if s == Sc::F32 {
                    *rng.pick(&[Sc::I32, Sc::U32])
                } else {
                    let mut from = cfg.numeric_sources().to_vec();
                    from.push(Sc::Bool);
                    *rng.pick(&from)
                };
                return e(ty, Kind::Cast(b(rgen(rng, T::scalar(from), d, cfg))));
            }
            if k == 3 {
                let vt = any_vec(rng, s);
                let v = rgen(rng, vt, d, cfg);
                let w = rgen(rng, v.ty, d, cfg);
                return m(ty, "dot", v, vec![w]);
            }
            numeric_op(rng, ty, d, cfg)
        }
    }
}
