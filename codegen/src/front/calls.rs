//! Builtin library: free functions (barriers, `select`, derivatives, packing, subgroup
//! collectives) and methods (math on scalars and vectors, swizzles, conversions, atomics,
//! textures). Each entry types its arguments and maps to one WGSL builtin.
//!
//! Convention: an operation *on a value* is a method, as in std/glam (`x.max(y)`, `v.dot(w)`,
//! `COUNT.fetch_add(1)`, `TEX.sample(S, uv)`); an operation without a natural receiver is a
//! free function (`select`, `workgroup_barrier`, `dpdx`, `pack4x8_unorm`, `subgroup_add`).

use super::build::mk;
use super::ctx::FnCtx;
use crate::ir::{Builtin, Expr, ExprKind, Scalar, Ty};
use proc_macro2::Span;
use syn::{Error, Result};

pub(super) fn plain(wgsl: &'static str) -> Builtin {
    Builtin {
        wgsl,
        subgroup: false,
        pointer_first: false,
    }
}

pub(super) fn call(b: Builtin, args: Vec<Expr>, ty: Ty, span: Span) -> Expr {
    mk(ExprKind::Builtin(b, args), ty, span)
}

const FLOAT_UNARY: &[(&str, &str)] = &[
    ("sqrt", "sqrt"),
    ("floor", "floor"),
    ("ceil", "ceil"),
    ("round", "round"),
    ("fract", "fract"),
    ("trunc", "trunc"),
    ("sin", "sin"),
    ("cos", "cos"),
    ("tan", "tan"),
    ("asin", "asin"),
    ("acos", "acos"),
    ("atan", "atan"),
    ("sinh", "sinh"),
    ("cosh", "cosh"),
    ("tanh", "tanh"),
    ("exp", "exp"),
    ("exp2", "exp2"),
    ("ln", "log"),
    ("log2", "log2"),
    ("signum", "sign"),
    ("to_radians", "radians"),
    ("to_degrees", "degrees"),
    ("saturate", "saturate"),
    ("inverse_sqrt", "inverseSqrt"),
];

const INT_UNARY: &[(&str, &str)] = &[
    ("count_ones", "countOneBits"),
    ("leading_zeros", "countLeadingZeros"),
    ("trailing_zeros", "countTrailingZeros"),
    ("reverse_bits", "reverseBits"),
];

pub(super) const ATOMICS: &[(&str, &str)] = &[
    ("fetch_add", "atomicAdd"),
    ("fetch_sub", "atomicSub"),
    ("fetch_min", "atomicMin"),
    ("fetch_max", "atomicMax"),
    ("fetch_and", "atomicAnd"),
    ("fetch_or", "atomicOr"),
    ("fetch_xor", "atomicXor"),
    ("swap", "atomicExchange"),
];

const SUBGROUP: &[(&str, &str)] = &[
    ("subgroup_broadcast_first", "subgroupBroadcastFirst"),
    ("subgroup_min", "subgroupMin"),
    ("subgroup_max", "subgroupMax"),
    ("subgroup_add", "subgroupAdd"),
    ("subgroup_mul", "subgroupMul"),
    ("subgroup_exclusive_add", "subgroupExclusiveAdd"),
    ("subgroup_inclusive_add", "subgroupInclusiveAdd"),
    ("subgroup_and", "subgroupAnd"),
    ("subgroup_or", "subgroupOr"),
    ("subgroup_xor", "subgroupXor"),
];

const PACK: &[(&str, &str, u8, bool)] = &[
    ("pack4x8_unorm", "pack4x8unorm", 4, true),
    ("pack4x8_snorm", "pack4x8snorm", 4, true),
    ("pack2x16_unorm", "pack2x16unorm", 2, true),
    ("pack2x16_snorm", "pack2x16snorm", 2, true),
    ("unpack4x8_unorm", "unpack4x8unorm", 4, false),
    ("unpack4x8_snorm", "unpack4x8snorm", 4, false),
    ("unpack2x16_unorm", "unpack2x16unorm", 2, false),
    ("unpack2x16_snorm", "unpack2x16snorm", 2, false),
    ("pack2x16_float", "pack2x16float", 2, true),
    ("unpack2x16_float", "unpack2x16float", 2, false),
];

const DERIVATIVES: &[(&str, &str)] = &[
    ("dpdx", "dpdx"),
    ("dpdy", "dpdy"),
    ("fwidth", "fwidth"),
    ("dpdx_fine", "dpdxFine"),
    ("dpdy_fine", "dpdyFine"),
    ("fwidth_fine", "fwidthFine"),
    ("dpdx_coarse", "dpdxCoarse"),
    ("dpdy_coarse", "dpdyCoarse"),
    ("fwidth_coarse", "fwidthCoarse"),
];

pub(super) fn lookup(table: &[(&str, &'static str)], name: &str) -> Option<&'static str> {
    table.iter().find(|(r, _)| *r == name).map(|(_, w)| *w)
}

impl FnCtx<'_> {
    pub(super) fn arity(&self, name: &str, args: &[Expr], n: usize, span: Span) -> Result<()> {
        if args.len() != n {
            return Err(Error::new(
                span,
                format!("`{name}` takes {n} argument(s), found {}", args.len()),
            ));
        }
        Ok(())
    }

    pub(super) fn same(&self, want: &Ty, arg: &Expr) -> Result<Ty> {
        want.unify(&arg.ty)
            .filter(|t| t.is_numeric() || *t == Ty::BOOL || *want == arg.ty)
            .ok_or_else(|| self.err_mismatch(want, arg))
    }

    pub(crate) fn free_fn(
        &mut self,
        name: &syn::Ident,
        args: Vec<Expr>,
        span: Span,
    ) -> Result<Expr> {
        let n = name.to_string();
        if n == "select" {
            self.arity(&n, &args, 3, span)?;
            if args[0].ty != Ty::BOOL {
                return Err(self.err_mismatch(&Ty::BOOL, &args[0]));
            }
            let ty = self.same(&args[1].ty, &args[2])?;
            #[expect(clippy::expect_used, reason = "the arity was checked above")]
            let [c, t, f]: [Expr; 3] = args.try_into().expect("arity checked");
            return Ok(call(plain("select"), vec![f, t, c], ty, span));
        }
        if n == "workgroup_barrier" || n == "storage_barrier" {
            self.arity(&n, &args, 0, span)?;
            let wgsl = if n == "workgroup_barrier" {
                "workgroupBarrier"
            } else {
                "storageBarrier"
            };
            return Ok(call(
                Builtin {
                    wgsl,
                    subgroup: false,
                    pointer_first: false,
                },
                args,
                Ty::Unit,
                span,
            ));
        }
        if let Some(w) = lookup(DERIVATIVES, &n) {
            self.arity(&n, &args, 1, span)?;
            if !args[0].ty.is_float_like() {
                return Err(Error::new(
                    args[0].span,
                    format!("`{n}` takes an `f32` or float vector"),
                ));
            }
            let ty = args[0].ty.concretize();
            return Ok(call(plain(w), args, ty, span));
        }
        if let Some(&(_, w, size, pack)) = PACK.iter().find(|p| p.0 == n) {
            self.arity(&n, &args, 1, span)?;
            let vec = Ty::Vector(size, Scalar::F32);
            let (input, out) = if pack { (vec, Ty::U32) } else { (Ty::U32, vec) };
            if !args[0].ty.converts_to(&input) {
                return Err(self.err_mismatch(&input, &args[0]));
            }
            return Ok(call(plain(w), args, out, span));
        }
        let sub = |wgsl| Builtin {
            wgsl,
            subgroup: true,
            pointer_first: false,
        };
        match n.as_str() {
            "subgroup_ballot" => {
                self.arity(&n, &args, 1, span)?;
                if args[0].ty != Ty::BOOL {
                    return Err(self.err_mismatch(&Ty::BOOL, &args[0]));
                }
                return Ok(call(
                    sub("subgroupBallot"),
                    args,
                    Ty::Vector(4, Scalar::U32),
                    span,
                ));
            }
            "subgroup_all" | "subgroup_any" => {
                self.arity(&n, &args, 1, span)?;
                if args[0].ty != Ty::BOOL {
                    return Err(self.err_mismatch(&Ty::BOOL, &args[0]));
                }
                let w = if n == "subgroup_all" {
                    "subgroupAll"
                } else {
                    "subgroupAny"
                };
                return Ok(call(sub(w), args, Ty::BOOL, span));
            }
            "subgroup_shuffle" => {
                self.arity(&n, &args, 2, span)?;
                if !args[0].ty.is_numeric()
                    || args[0].ty == Ty::U64
                    || !args[1].ty.converts_to(&Ty::U32)
                {
                    return Err(Error::new(span, "`subgroup_shuffle(value, lane: u32)`"));
                }
                let ty = args[0].ty.concretize();
                return Ok(call(sub("subgroupShuffle"), args, ty, span));
            }
            _ => {}
        }
        if let Some(w) = lookup(SUBGROUP, &n) {
            self.arity(&n, &args, 1, span)?;
            let ok = if matches!(n.as_str(), "subgroup_and" | "subgroup_or" | "subgroup_xor") {
                args[0].ty.is_int_like()
            } else {
                args[0].ty.is_numeric()
            };
            if !ok || args[0].ty == Ty::U64 {
                return Err(Error::new(
                    args[0].span,
                    format!("`{n}` does not accept `{}`", self.ty_name(&args[0].ty)),
                ));
            }
            let ty = args[0].ty.concretize();
            return Ok(call(sub(w), args, ty, span));
        }
        Err(Error::new(
            name.span(),
            format!(
                "cannot find function `{n}`: it is neither a function of this module nor a DSL builtin (math is written as methods, e.g. `x.max(y)`, `v.dot(w)`)"
            ),
        ))
    }

    pub(crate) fn method(
        &mut self,
        recv: Expr,
        method: &syn::Ident,
        args: Vec<Expr>,
        span: Span,
    ) -> Result<Expr> {
        let recv = self.auto_deref(recv);
        if method == "uniform_load" {
            return self.uniform_load(recv, args, span);
        }
        match recv.ty.clone() {
            Ty::Atomic(s) => self.atomic_method(recv, s, method, args, span),
            Ty::Texture(_) | Ty::StorageTexture(..) => {
                self.texture_method(recv, method, args, span)
            }
            Ty::RuntimeArray(_) if method == "len" && matches!(recv.kind, ExprKind::Global(_)) => {
                self.arity("len", &args, 0, span)?;
                let b = Builtin {
                    wgsl: "arrayLength",
                    subgroup: false,
                    pointer_first: true,
                };
                Ok(call(b, vec![recv], Ty::U32, span))
            }
            _ => self.math_method(recv, method, args, span),
        }
    }

    pub(super) fn unknown_method(&self, recv: &Expr, method: &syn::Ident) -> Error {
        Error::new(
            method.span(),
            format!(
                "unknown method `{method}` on `{}`; see the language guide for the supported methods",
                self.ty_name(&recv.ty)
            ),
        )
    }

    fn math_method(
        &mut self,
        recv: Expr,
        method: &syn::Ident,
        mut args: Vec<Expr>,
        span: Span,
    ) -> Result<Expr> {
        let m = method.to_string();
        let rty = recv.ty.clone();
        if rty == Ty::U64 && !matches!(m.as_str(), "min" | "max") {
            return Err(Error::new(
                method.span(),
                format!(
                    "`{m}` is not available on `u64`: it has the operators, comparisons, `as`, `min` and `max`; convert to `u32` for the rest"
                ),
            ));
        }
        let float = rty.is_float_like();
        let mut all = vec![recv.clone()];
        if let Some(w) = lookup(FLOAT_UNARY, &m).filter(|_| float) {
            self.arity(&m, &args, 0, span)?;
            return Ok(call(plain(w), all, rty.concretize(), span));
        }
        if let Some(w) = lookup(INT_UNARY, &m).filter(|_| rty.is_int_like()) {
            self.arity(&m, &args, 0, span)?;
            return Ok(call(plain(w), all, rty.concretize(), span));
        }
        // Swizzles: `.xy()`, `.zyx()`, ...
        if let Ty::Vector(n, s) = rty
            && (2..=4).contains(&m.len())
            && m.chars().all(|c| "xyzw"[..n as usize].contains(c))
        {
            self.arity(&m, &args, 0, span)?;
            return Ok(mk(
                ExprKind::Swizzle(Box::new(recv), m.clone()),
                Ty::Vector(m.len() as u8, s),
                span,
            ));
        }
        let two = |cx: &Self, args: &[Expr]| -> Result<Ty> {
            cx.arity(&m, args, 1, span)?;
            cx.same(&rty, &args[0])
        };
        match (m.as_str(), &rty) {
            ("to_bits", Ty::Scalar(Scalar::F32 | Scalar::AbstractFloat))
            | ("from_bits", Ty::Scalar(Scalar::U32 | Scalar::I32 | Scalar::AbstractInt)) => {
                self.arity(&m, &args, 0, span)?;
                let (w, ty) = if m == "to_bits" {
                    ("bitcast<u32>", Ty::U32)
                } else {
                    ("bitcast<f32>", Ty::F32)
                };
                Ok(call(plain(w), all, ty, span))
            }
            ("abs", t) if t.is_numeric() => {
                self.arity(&m, &args, 0, span)?;
                Ok(call(plain("abs"), all, rty.concretize(), span))
            }
            ("min" | "max" | "powf" | "atan2" | "step", t)
                if t.is_numeric() && (matches!(m.as_str(), "min" | "max") || float) =>
            {
                let ty = two(self, &args)?;
                let w = match m.as_str() {
                    "powf" => "pow",
                    "atan2" => "atan2",
                    "step" => "step",
                    "min" => "min",
                    _ => "max",
                };
                if m == "step" {
                    // `x.step(edge)` is WGSL `step(edge, x)`.
                    all.insert(0, args.remove(0));
                } else {
                    all.extend(args);
                }
                Ok(call(plain(w), all, ty.concretize(), span))
            }
            ("clamp", t) if t.is_numeric() => {
                self.arity(&m, &args, 2, span)?;
                let ty = self.same(&rty, &args[0])?;
                let ty = self.same(&ty, &args[1])?;
                all.extend(args);
                Ok(call(plain("clamp"), all, ty.concretize(), span))
            }
            ("mul_add", _) if float => {
                self.arity(&m, &args, 2, span)?;
                self.same(&rty, &args[0])?;
                self.same(&rty, &args[1])?;
                all.extend(args);
                Ok(call(plain("fma"), all, rty.concretize(), span))
            }
            ("smoothstep", _) if float => {
                self.arity(&m, &args, 2, span)?;
                self.same(&rty, &args[0])?;
                self.same(&rty, &args[1])?;
                args.push(recv);
                Ok(call(plain("smoothstep"), args, rty.concretize(), span))
            }
            ("lerp", _) if float => {
                self.arity(&m, &args, 2, span)?;
                self.same(&rty, &args[0])?;
                if !args[1].ty.converts_to(&Ty::F32) && !args[1].ty.converts_to(&rty) {
                    return Err(self.err_mismatch(&Ty::F32, &args[1]));
                }
                all.extend(args);
                Ok(call(plain("mix"), all, rty.concretize(), span))
            }
            ("dot", Ty::Vector(_, s)) if s.is_numeric() => {
                two(self, &args)?;
                all.extend(args);
                Ok(call(plain("dot"), all, Ty::Scalar(s.concretize()), span))
            }
            ("length_squared", Ty::Vector(..)) if float => {
                self.arity(&m, &args, 0, span)?;
                Ok(call(plain("dot"), vec![recv.clone(), recv], Ty::F32, span))
            }
            ("length", Ty::Vector(..)) if float => {
                self.arity(&m, &args, 0, span)?;
                Ok(call(plain("length"), all, Ty::F32, span))
            }
            ("normalize", Ty::Vector(..)) if float => {
                self.arity(&m, &args, 0, span)?;
                Ok(call(plain("normalize"), all, rty.concretize(), span))
            }
            ("distance", Ty::Vector(..)) if float => {
                two(self, &args)?;
                all.extend(args);
                Ok(call(plain("distance"), all, Ty::F32, span))
            }
            ("cross", Ty::Vector(3, _)) if float => {
                two(self, &args)?;
                all.extend(args);
                Ok(call(plain("cross"), all, Ty::Vector(3, Scalar::F32), span))
            }
            ("reflect", Ty::Vector(..)) if float => {
                two(self, &args)?;
                all.extend(args);
                Ok(call(plain("reflect"), all, rty.concretize(), span))
            }
            ("extend", Ty::Vector(n, s)) if *n < 4 => {
                self.arity(&m, &args, 1, span)?;
                self.same(&Ty::Scalar(*s), &args[0])?;
                all.extend(args);
                Ok(mk(ExprKind::Construct(all), Ty::Vector(n + 1, *s), span))
            }
            ("truncate", Ty::Vector(n, s)) if *n > 2 => {
                self.arity(&m, &args, 0, span)?;
                let sw = &"xyz"[..(*n - 1) as usize];
                Ok(mk(
                    ExprKind::Swizzle(Box::new(recv), sw.into()),
                    Ty::Vector(n - 1, *s),
                    span,
                ))
            }
            ("transpose", Ty::Matrix(c, r)) => {
                self.arity(&m, &args, 0, span)?;
                Ok(call(plain("transpose"), all, Ty::Matrix(*r, *c), span))
            }
            ("determinant", Ty::Matrix(c, r)) if c == r => {
                self.arity(&m, &args, 0, span)?;
                Ok(call(plain("determinant"), all, Ty::F32, span))
            }
            ("col", Ty::Matrix(_, r)) => {
                self.arity(&m, &args, 1, span)?;
                let i = args.remove(0);
                if !matches!(i.ty, Ty::Scalar(s) if s.is_int32()) {
                    return Err(self.err_mismatch(&Ty::U32, &i));
                }
                Ok(mk(
                    ExprKind::Index(Box::new(recv), Box::new(i)),
                    Ty::Vector(*r, Scalar::F32),
                    span,
                ))
            }
            (conv, Ty::Vector(n, _)) if conv.starts_with("as_") => {
                let target = super::types::vec_or_mat_named(
                    &conv[3..].to_ascii_uppercase().replace("VEC", "Vec"),
                )
                .filter(|t| matches!(t, Ty::Vector(k, s) if k == n && *s != Scalar::Bool))
                .ok_or_else(|| self.unknown_method(&recv, method))?;
                self.arity(&m, &args, 0, span)?;
                Ok(mk(ExprKind::Construct(all), target, span))
            }
            _ => Err(self.unknown_method(&recv, method)),
        }
    }
}
