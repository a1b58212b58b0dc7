//! Calls and constructors: module function calls (with `&mut` in-out arguments), vector and
//! matrix constructors, UFCS (`f32::max(a, b)`), struct literals, and place checks.

use super::build::{NOT_CONST, mk};
use super::ctx::FnCtx;
use crate::ir::{Expr, ExprKind, Scalar, Ty};
use proc_macro2::Span;
use syn::spanned::Spanned;
use syn::{Error, Result};

impl FnCtx<'_> {
    pub(crate) fn struct_lit(&mut self, s: &syn::ExprStruct) -> Result<Expr> {
        let span = s.path.span();
        if self.const_only {
            return Err(Error::new(span, NOT_CONST));
        }
        let name = s
            .path
            .get_ident()
            .map(|i| i.to_string())
            .unwrap_or_default();
        let Some(&id) = self.m.struct_ids.get(&name) else {
            return Err(Error::new(span, format!("unknown struct `{name}`")));
        };
        if let Some(rest) = &s.rest {
            return Err(Error::new(
                rest.span(),
                "`..base` is not supported; list every field",
            ));
        }
        let fields = self.m.module.structs[id].fields.clone();
        let mut values: Vec<Option<Expr>> = vec![None; fields.len()];
        for fv in &s.fields {
            let syn::Member::Named(fname) = &fv.member else {
                return Err(Error::new(fv.member.span(), "expected a named field"));
            };
            let Some(i) = fields.iter().position(|f| *fname == f.name) else {
                return Err(Error::new(
                    fname.span(),
                    format!("struct `{name}` has no field `{fname}`"),
                ));
            };
            if values[i].is_some() {
                return Err(Error::new(
                    fname.span(),
                    format!("field `{fname}` specified twice"),
                ));
            }
            values[i] = Some(self.expr_as(&fv.expr, &fields[i].ty)?);
        }
        let missing: Vec<_> = fields
            .iter()
            .zip(&values)
            .filter(|(_, v)| v.is_none())
            .map(|(f, _)| f.name.as_str())
            .collect();
        if !missing.is_empty() {
            return Err(Error::new(
                span,
                format!("missing fields in `{name}` literal: {}", missing.join(", ")),
            ));
        }
        #[expect(clippy::expect_used, reason = "missing fields were reported above")]
        let args = values.into_iter().map(|v| v.expect("checked")).collect();
        Ok(mk(ExprKind::Construct(args), Ty::Struct(id), s.span()))
    }

    pub(crate) fn call(&mut self, c: &syn::ExprCall) -> Result<Expr> {
        let span = c.span();
        let syn::Expr::Path(p) = &*c.func else {
            return Err(Error::new(
                c.func.span(),
                "only named functions can be called",
            ));
        };
        let segs: Vec<&syn::Ident> = p.path.segments.iter().map(|s| &s.ident).collect();
        let is_ctor = matches!(segs.as_slice(), [.., owner, m]
            if super::types::vec_or_mat_named(&owner.to_string()).is_some()
                && matches!(m.to_string().as_str(), "new" | "splat" | "from_cols"));
        if self.const_only && !is_ctor {
            return Err(Error::new(span, NOT_CONST));
        }
        if let [name] = segs.as_slice() {
            if let Some(&f) = self.m.fn_ids.get(&name.to_string()) {
                return self.user_call(f, c, name.span());
            }
            let args = c
                .args
                .iter()
                .map(|a| self.value_arg(a))
                .collect::<Result<Vec<_>>>()?;
            return self.free_fn(name, args, span);
        }
        let [.., owner, method] = segs.as_slice() else {
            unreachable!("path has segments")
        };
        let owner_s = owner.to_string();
        if let Some(ty) = super::types::vec_or_mat_named(&owner_s) {
            let args = c
                .args
                .iter()
                .map(|a| self.value_arg(a))
                .collect::<Result<Vec<_>>>()?;
            if let Some(e) = self.constructor(&ty, method, &args, span)? {
                return Ok(e);
            }
            return self.ufcs(args, method, span);
        }
        if super::types::scalar_named(&owner_s).is_some() {
            let args = c
                .args
                .iter()
                .map(|a| self.value_arg(a))
                .collect::<Result<Vec<_>>>()?;
            return self.ufcs(args, method, span);
        }
        Err(Error::new(
            c.func.span(),
            format!(
                "unknown function `{}`",
                segs.iter()
                    .map(|s| s.to_string())
                    .collect::<Vec<_>>()
                    .join("::")
            ),
        ))
    }

    /// `f32::max(a, b)` is `a.max(b)`.
    fn ufcs(&mut self, mut args: Vec<Expr>, method: &syn::Ident, span: Span) -> Result<Expr> {
        if args.is_empty() {
            return Err(Error::new(
                method.span(),
                format!("unknown associated function `{method}`"),
            ));
        }
        let recv = args.remove(0);
        self.method(recv, method, args, span)
    }

    fn constructor(
        &mut self,
        ty: &Ty,
        method: &syn::Ident,
        args: &[Expr],
        span: Span,
    ) -> Result<Option<Expr>> {
        let name = self.ty_name(ty);
        #[expect(
            clippy::expect_used,
            reason = "called only for vector and matrix types, which have a scalar"
        )]
        let s = ty.scalar().expect("vector or matrix");
        match (method.to_string().as_str(), ty) {
            ("new", Ty::Vector(n, _)) => {
                let mut count = 0;
                for a in args {
                    match &a.ty {
                        Ty::Scalar(t) if t.unify(s) == Some(s) => count += 1,
                        Ty::Vector(m, t) if t.unify(s) == Some(s) => count += *m as usize,
                        _ => {
                            return Err(Error::new(
                                a.span,
                                format!(
                                    "`{name}::new` takes `{}` components, found `{}`",
                                    s.rust_name(),
                                    self.ty_name(&a.ty)
                                ),
                            ));
                        }
                    }
                }
                if count != *n as usize {
                    return Err(Error::new(
                        span,
                        format!("`{name}::new` needs {n} components in total, found {count}"),
                    ));
                }
                Ok(Some(mk(
                    ExprKind::Construct(args.to_vec()),
                    ty.clone(),
                    span,
                )))
            }
            ("splat", Ty::Vector(..)) => match args {
                [a] if a.ty.converts_to(&Ty::Scalar(s)) => Ok(Some(mk(
                    ExprKind::Construct(args.to_vec()),
                    ty.clone(),
                    span,
                ))),
                _ => Err(Error::new(
                    span,
                    format!("`{name}::splat` takes one `{}`", s.rust_name()),
                )),
            },
            ("from_cols", Ty::Matrix(c, r)) => {
                let col = Ty::Vector(*r, Scalar::F32);
                if args.len() != *c as usize || args.iter().any(|a| !a.ty.converts_to(&col)) {
                    return Err(Error::new(
                        span,
                        format!(
                            "`{name}::from_cols` takes {c} `{}` columns",
                            self.ty_name(&col)
                        ),
                    ));
                }
                Ok(Some(mk(
                    ExprKind::Construct(args.to_vec()),
                    ty.clone(),
                    span,
                )))
            }
            ("new" | "splat" | "from_cols", _) => Err(Error::new(
                method.span(),
                format!(
                    "`{name}::{method}` does not exist; vectors have `new`/`splat`, matrices `from_cols`"
                ),
            )),
            _ => Ok(None),
        }
    }

    fn user_call(&mut self, f: usize, c: &syn::ExprCall, name_span: Span) -> Result<Expr> {
        let func = &self.m.module.functions[f];
        if func.stage.is_some() {
            return Err(Error::new(
                name_span,
                "entry points cannot be called; move the shared code into a helper function",
            ));
        }
        if c.args.len() != func.params.len() {
            return Err(Error::new(
                c.span(),
                format!(
                    "`{}` takes {} arguments, found {}",
                    func.name,
                    func.params.len(),
                    c.args.len()
                ),
            ));
        }
        let param_tys: Vec<Ty> = func
            .params
            .iter()
            .map(|p| func.locals[p.local].ty.clone())
            .collect();
        let mut args = vec![];
        for (a, pty) in c.args.iter().zip(&param_tys) {
            let arg = match pty {
                Ty::Ptr(inner) => self.mut_arg(a, inner)?,
                t => self.expr_as(a, t)?,
            };
            args.push(arg);
        }
        self.calls.push((f, name_span));
        let ret = self.m.module.functions[f].ret.clone();
        Ok(mk(ExprKind::Call(f, args), ret, c.span()))
    }

    fn mut_arg(&mut self, a: &syn::Expr, inner: &Ty) -> Result<Expr> {
        let want_msg = format!(
            "expected `&mut {}` here: pass `&mut local`",
            self.ty_name(inner)
        );
        let want = || want_msg.clone();
        match a {
            syn::Expr::Reference(r) if r.mutability.is_some() => {
                let place = self.expr(&r.expr)?;
                self.check_place(&place, true)?;
                if !root_is_function_local(&place, self) {
                    return Err(Error::new(
                        r.expr.span(),
                        "only local variables (or parts of them) can be passed as `&mut`; copy the value into a `let mut` first",
                    ));
                }
                if place.ty != *inner {
                    return Err(self.err_mismatch(inner, &place));
                }
                let span = a.span();
                Ok(mk(
                    ExprKind::AddrOf(Box::new(place)),
                    Ty::Ptr(Box::new(inner.clone())),
                    span,
                ))
            }
            _ => {
                let x = self.expr(a).map_err(|_| Error::new(a.span(), want()))?;
                if x.ty == Ty::Ptr(Box::new(inner.clone())) && matches!(x.kind, ExprKind::Local(_))
                {
                    Ok(x)
                } else {
                    Err(Error::new(a.span(), want()))
                }
            }
        }
    }

    /// Checks that `e` is an assignable place (when `write`), saying why not.
    pub(crate) fn check_place(&self, e: &Expr, write: bool) -> Result<()> {
        match &e.kind {
            ExprKind::Local(l) => {
                let local = &self.locals[*l];
                if write && !local.mutable {
                    // The name as written (the WGSL name may carry a shadowing suffix).
                    let name = self.source_name(*l).unwrap_or(&local.name);
                    return Err(Error::new(
                        e.span,
                        format!("cannot assign to `{name}`: it is not declared `mut`"),
                    ));
                }
                Ok(())
            }
            ExprKind::Deref(p) if matches!(p.kind, ExprKind::Local(_)) => Ok(()),
            ExprKind::Global(g) => {
                let glob = &self.m.module.globals[*g];
                match glob.space {
                    crate::ir::Space::Workgroup
                    | crate::ir::Space::Storage { read_write: true } => Ok(()),
                    crate::ir::Space::Storage { read_write: false } => Err(Error::new(
                        e.span,
                        format!(
                            "cannot write to `{}`: the storage buffer is read-only; declare it `#[storage(.., read_write)]`",
                            glob.name
                        ),
                    )),
                    crate::ir::Space::Uniform => Err(Error::new(
                        e.span,
                        format!(
                            "cannot write to `{}`: uniform buffers are read-only",
                            glob.name
                        ),
                    )),
                    crate::ir::Space::Handle => Err(Error::new(
                        e.span,
                        format!(
                            "cannot assign to `{}`; write textures with `.store(..)`",
                            glob.name
                        ),
                    )),
                }
            }
            ExprKind::Field(b, _) | ExprKind::Index(b, _) => self.check_place(b, write),
            ExprKind::Swizzle(b, s) if s.len() == 1 => self.check_place(b, write),
            _ => Err(Error::new(
                e.span,
                "this expression is not assignable; assign to a `let mut`, a field, an element or a writable static",
            )),
        }
    }
}

fn root_is_function_local(e: &Expr, cx: &FnCtx<'_>) -> bool {
    match &e.kind {
        ExprKind::Local(l) => !matches!(cx.locals[*l].ty, Ty::Ptr(_)),
        ExprKind::Field(b, _) | ExprKind::Index(b, _) => root_is_function_local(b, cx),
        _ => false,
    }
}
