//! Resource methods: atomics on workgroup/storage places and texture loads, stores, sampling
//! and queries, each typed against its receiver and mapped to one WGSL builtin.

use super::calls::{ATOMICS, call, lookup, plain};
use super::ctx::FnCtx;
use crate::ir::{Builtin, Expr, ExprKind, Scalar, Space, TexKind, Ty};
use proc_macro2::Span;
use syn::{Error, Result};

impl FnCtx<'_> {
    pub(super) fn atomic_method(
        &mut self,
        recv: Expr,
        s: Scalar,
        method: &syn::Ident,
        args: Vec<Expr>,
        span: Span,
    ) -> Result<Expr> {
        let m = method.to_string();
        self.check_place(&recv, false)?;
        let atomic = |wgsl| Builtin {
            wgsl,
            subgroup: false,
            pointer_first: true,
        };
        let mut all = vec![recv.clone()];
        let value = Ty::Scalar(s);
        if s == Scalar::U64 {
            return self.atomic64_method(all, &m, method, args, span);
        }
        if m == "load" {
            self.arity(&m, &args, 0, span)?;
            return Ok(call(atomic("atomicLoad"), all, value, span));
        }
        let wgsl = match m.as_str() {
            "store" => "atomicStore",
            other => lookup(ATOMICS, other).ok_or_else(|| {
                Error::new(method.span(), format!("unknown atomic method `{m}`; expected load, store, fetch_add, fetch_sub, fetch_min, fetch_max, fetch_and, fetch_or, fetch_xor or swap"))
            })?,
        };
        self.arity(&m, &args, 1, span)?;
        if !args[0].ty.converts_to(&value) {
            return Err(self.err_mismatch(&value, &args[0]));
        }
        all.extend(args);
        let ret = if m == "store" { Ty::Unit } else { value };
        Ok(call(atomic(wgsl), all, ret, span))
    }

    /// `X.uniform_load()` on a workgroup static (or an element or field of one, an atomic
    /// too): WGSL's `workgroupUniformLoad(&X)`, a workgroup barrier and then a load whose value
    /// every invocation shares, so control flow that depends on it (a loop with barriers in
    /// it) is uniform to WGSL's analysis. It must itself be reached by the whole workgroup.
    pub(super) fn uniform_load(&mut self, recv: Expr, args: Vec<Expr>, span: Span) -> Result<Expr> {
        self.arity("uniform_load", &args, 0, span)?;
        if !self.rooted_in_workgroup(&recv) {
            return Err(Error::new(
                recv.span,
                "`uniform_load()` reads a `#[workgroup]` static, or an element or field of one \
                 (WGSL's workgroupUniformLoad); other values need no uniform load",
            ));
        }
        let ty = match &recv.ty {
            Ty::Atomic(s) => Ty::Scalar(*s),
            t if t.is_constructible() => t.clone(),
            t => {
                return Err(Error::new(
                    recv.span,
                    format!(
                        "`uniform_load()` cannot load a `{}`: a runtime-sized array has no value",
                        self.ty_name(t)
                    ),
                ));
            }
        };
        let b = Builtin {
            wgsl: "workgroupUniformLoad",
            subgroup: false,
            pointer_first: true,
        };
        Ok(call(b, vec![recv], ty, span))
    }

    /// Whether `e` is a workgroup static, or an element or field of one.
    fn rooted_in_workgroup(&self, e: &Expr) -> bool {
        match &e.kind {
            ExprKind::Global(g) => self.m.module.globals[*g].space == Space::Workgroup,
            ExprKind::Field(b, _) | ExprKind::Index(b, _) => self.rooted_in_workgroup(b),
            _ => false,
        }
    }

    /// `fetch_min(v)`/`fetch_max(v)` on an `Atomic<u64>`: statements of type `()`, printed as
    /// bare `atomicMin(&X[i], v);`, which naga lowers without a result, the form wgpu's
    /// `SHADER_INT64_ATOMIC_MIN_MAX` allows (on storage buffers: the only place an
    /// `Atomic<u64>` may live). Every other atomic operation is an error here.
    fn atomic64_method(
        &mut self,
        mut all: Vec<Expr>,
        m: &str,
        method: &syn::Ident,
        args: Vec<Expr>,
        span: Span,
    ) -> Result<Expr> {
        let wgsl = match m {
            "fetch_min" => "atomicMin",
            "fetch_max" => "atomicMax",
            _ => {
                return Err(Error::new(
                    method.span(),
                    format!(
                        "`{m}` is not available on `Atomic<u64>`: the device's 64-bit atomics (wgpu's SHADER_INT64_ATOMIC_MIN_MAX) are only `fetch_min(v)` and `fetch_max(v)`, without a returned value"
                    ),
                ));
            }
        };
        self.arity(m, &args, 1, span)?;
        if !args[0].ty.converts_to(&Ty::U64) {
            return Err(self.err_mismatch(&Ty::U64, &args[0]));
        }
        all.extend(args);
        let b = Builtin {
            wgsl,
            subgroup: false,
            pointer_first: true,
        };
        Ok(call(b, all, Ty::Unit, span))
    }

    fn sampler_arg(&self, e: &Expr, comparison: bool) -> Result<()> {
        let ok = matches!(e.kind, ExprKind::Global(_)) && e.ty == Ty::Sampler { comparison };
        if !ok {
            let want = if comparison {
                "a `SamplerComparison` static"
            } else {
                "a `Sampler` static"
            };
            let found = self.ty_name(&e.ty);
            return Err(Error::new(
                e.span,
                format!("expected {want}, found `{found}`"),
            ));
        }
        Ok(())
    }

    pub(super) fn texture_method(
        &mut self,
        recv: Expr,
        method: &syn::Ident,
        args: Vec<Expr>,
        span: Span,
    ) -> Result<Expr> {
        let m = method.to_string();
        let ExprKind::Global(g) = recv.kind else {
            return Err(Error::new(
                recv.span,
                "textures are used directly through their `static`",
            ));
        };
        debug_assert_eq!(self.m.module.globals[g].space, Space::Handle);
        let ivec2 = |e: &Expr| matches!(e.ty, Ty::Vector(2, s) if s.is_int());
        let int = |e: &Expr| matches!(e.ty, Ty::Scalar(s) if s.is_int32());
        let uv_ok = |e: &Expr| e.ty.converts_to(&Ty::Vector(2, Scalar::F32));
        let mut all = vec![recv.clone()];
        let tyname = self.ty_name(&recv.ty);
        let usage = |sig: &str| Error::new(span, format!("expected `{sig}` for `{tyname}`"));
        match recv.ty.clone() {
            Ty::Texture(t) => {
                let texel = match t.kind {
                    TexKind::Depth => Ty::F32,
                    TexKind::Sampled(s) => Ty::Vector(4, s),
                };
                let layer = usize::from(t.arrayed);
                match m.as_str() {
                    "load" => {
                        let n = 2 + layer;
                        let sig = if t.arrayed {
                            "load(coords: UVec2, layer: u32, level: u32)"
                        } else if t.multisampled {
                            "load(coords: UVec2, sample_index: u32)"
                        } else {
                            "load(coords: UVec2, level: u32)"
                        };
                        if args.len() != n || !ivec2(&args[0]) || !args[1..].iter().all(int) {
                            return Err(usage(sig));
                        }
                        all.extend(args);
                        Ok(call(plain("textureLoad"), all, texel, span))
                    }
                    "sample"
                    | "sample_level"
                    | "sample_grad"
                    | "sample_compare"
                    | "sample_compare_level" => {
                        let compare = m.starts_with("sample_compare");
                        let grad = m == "sample_grad";
                        // Arguments after the sampler, the coordinates and the layer.
                        let extra = match m.as_str() {
                            "sample" => 0,
                            "sample_grad" => 2,
                            _ => 1,
                        };
                        let sig = match (m.as_str(), t.arrayed) {
                            ("sample", false) => "sample(sampler, uv: Vec2)",
                            ("sample", true) => "sample(sampler, uv: Vec2, layer: u32)",
                            ("sample_level", false) => "sample_level(sampler, uv: Vec2, level)",
                            ("sample_level", true) => {
                                "sample_level(sampler, uv: Vec2, layer: u32, level)"
                            }
                            ("sample_grad", false) => {
                                "sample_grad(sampler, uv: Vec2, ddx: Vec2, ddy: Vec2)"
                            }
                            ("sample_grad", true) => {
                                "sample_grad(sampler, uv: Vec2, layer: u32, ddx: Vec2, ddy: Vec2)"
                            }
                            (_, false) => "sample_compare(sampler, uv: Vec2, depth_ref: f32)",
                            (_, true) => {
                                "sample_compare(sampler, uv: Vec2, layer: u32, depth_ref: f32)"
                            }
                        };
                        if t.multisampled
                            || (compare && t.kind != TexKind::Depth)
                            || matches!(t.kind, TexKind::Sampled(s) if s != Scalar::F32)
                        {
                            return Err(Error::new(
                                method.span(),
                                format!("`{tyname}` cannot be sampled with `{m}`; use `load`"),
                            ));
                        }
                        if grad && t.kind == TexKind::Depth {
                            // WGSL's `textureSampleGrad` has no depth overloads.
                            return Err(Error::new(
                                method.span(),
                                format!(
                                    "`{tyname}` cannot be sampled with `sample_grad` (WGSL has no gradient sampling of depth textures); use `sample_level`"
                                ),
                            ));
                        }
                        if args.len() != 2 + layer + extra
                            || !uv_ok(&args[1])
                            || (t.arrayed && !int(&args[2]))
                        {
                            return Err(usage(sig));
                        }
                        self.sampler_arg(&args[0], compare)?;
                        let trailing = &args[2 + layer..];
                        let ok = if grad {
                            // `ddx` and `ddy`: the derivatives of `uv`.
                            trailing.iter().all(uv_ok)
                        } else if t.kind == TexKind::Depth && m == "sample_level" {
                            trailing.iter().all(int)
                        } else {
                            trailing.iter().all(|e| e.ty.converts_to(&Ty::F32))
                        };
                        if !ok {
                            return Err(usage(sig));
                        }
                        let w = match m.as_str() {
                            "sample" => "textureSample",
                            "sample_level" => "textureSampleLevel",
                            "sample_grad" => "textureSampleGrad",
                            "sample_compare" => "textureSampleCompare",
                            _ => "textureSampleCompareLevel",
                        };
                        all.extend(args);
                        let ty = if compare { Ty::F32 } else { texel };
                        Ok(call(plain(w), all, ty, span))
                    }
                    "dimensions" | "num_layers" | "num_samples" | "num_levels" => {
                        self.arity(&m, &args, 0, span)?;
                        let (w, ty) = match m.as_str() {
                            "dimensions" => ("textureDimensions", Ty::Vector(2, Scalar::U32)),
                            "num_layers" if t.arrayed => ("textureNumLayers", Ty::U32),
                            "num_samples" if t.multisampled => ("textureNumSamples", Ty::U32),
                            "num_levels" if !t.multisampled => ("textureNumLevels", Ty::U32),
                            _ => return Err(self.unknown_method(&recv, method)),
                        };
                        Ok(call(plain(w), all, ty, span))
                    }
                    _ => Err(self.unknown_method(&recv, method)),
                }
            }
            Ty::StorageTexture(f, access) => {
                use crate::ir::Access;
                let texel = Ty::Vector(4, f.scalar);
                match m.as_str() {
                    "load" => {
                        if access == Access::Write {
                            return Err(Error::new(
                                method.span(),
                                "this storage texture is `Write`; declare it `Read` or `ReadWrite` to load",
                            ));
                        }
                        if args.len() != 1 || !ivec2(&args[0]) {
                            return Err(usage("load(coords: UVec2)"));
                        }
                        all.extend(args);
                        Ok(call(plain("textureLoad"), all, texel, span))
                    }
                    "store" => {
                        if access == Access::Read {
                            return Err(Error::new(
                                method.span(),
                                "this storage texture is `Read`; declare it `Write` or `ReadWrite` to store",
                            ));
                        }
                        if args.len() != 2 || !ivec2(&args[0]) || !args[1].ty.converts_to(&texel) {
                            return Err(usage(&format!(
                                "store(coords: UVec2, value: {})",
                                self.ty_name(&texel)
                            )));
                        }
                        all.extend(args);
                        Ok(call(plain("textureStore"), all, Ty::Unit, span))
                    }
                    "dimensions" => {
                        self.arity(&m, &args, 0, span)?;
                        Ok(call(
                            plain("textureDimensions"),
                            all,
                            Ty::Vector(2, Scalar::U32),
                            span,
                        ))
                    }
                    _ => Err(self.unknown_method(&recv, method)),
                }
            }
            _ => unreachable!("texture_method is called for textures"),
        }
    }
}
