//! Statement lowering: `let`, assignment, `if`/`else`, `for` over ranges, `while`, `loop`,
//! `break`, `continue`, `return`, blocks and call statements.

use super::ctx::FnCtx;
use super::ops::compound_op;
use super::types::TyPos;
use crate::ir::{Block, Expr, ExprKind, Stmt, Ty};
use syn::spanned::Spanned;
use syn::{Error, Result};

impl FnCtx<'_> {
    /// A function body: a trailing expression becomes `return`.
    pub(crate) fn fn_body(&mut self, b: &syn::Block) -> Result<Block> {
        self.block_inner(&b.stmts, true)
    }

    fn block(&mut self, b: &syn::Block) -> Result<Block> {
        self.push_scope();
        let r = self.block_inner(&b.stmts, false);
        self.pop_scope();
        r
    }

    fn block_inner(&mut self, stmts: &[syn::Stmt], fn_tail: bool) -> Result<Block> {
        let mut out = vec![];
        for (i, s) in stmts.iter().enumerate() {
            let last = i + 1 == stmts.len();
            match s {
                syn::Stmt::Local(l) => out.push(self.local(l)?),
                syn::Stmt::Item(item) => {
                    return Err(Error::new(
                        item.span(),
                        "items inside functions are not supported; declare them at module level",
                    ));
                }
                syn::Stmt::Macro(m) => {
                    return Err(Error::new(
                        m.mac.path.span(),
                        "macros are not supported in shader code",
                    ));
                }
                syn::Stmt::Expr(e, semi) => {
                    let tail = semi.is_none() && last && fn_tail;
                    out.push(self.expr_stmt(e, semi.is_some(), tail)?);
                }
            }
        }
        Ok(out)
    }

    fn local(&mut self, l: &syn::Local) -> Result<Stmt> {
        let span = l.span();
        let Some(init) = &l.init else {
            return Err(Error::new(
                span,
                "`let` needs an initial value in shader code",
            ));
        };
        if let Some((else_tok, _)) = &init.diverge {
            return Err(Error::new(else_tok.span, "`let .. else` is not supported"));
        }
        let (pat, annotated) = match &l.pat {
            syn::Pat::Type(pt) => (&*pt.pat, Some(self.lower_type(&pt.ty, TyPos::Value)?)),
            p => (p, None),
        };
        let value = match &annotated {
            Some(t) => self.expr_as(&init.expr, t)?,
            None => self.expr(&init.expr)?,
        };
        match pat {
            syn::Pat::Wild(_) => Ok(Stmt::Let {
                local: None,
                init: value,
                span,
            }),
            syn::Pat::Ident(pi) if pi.by_ref.is_none() && pi.subpat.is_none() => {
                let ty = annotated.unwrap_or_else(|| value.ty.concretize());
                if !ty.is_constructible() || matches!(ty, Ty::Unit) {
                    return Err(Error::new(
                        init.expr.span(),
                        format!(
                            "a value of type `{}` cannot be stored in a local variable",
                            self.ty_name(&ty)
                        ),
                    ));
                }
                let local = self.declare(
                    &pi.ident.to_string(),
                    ty,
                    pi.mutability.is_some(),
                    pi.ident.span(),
                );
                Ok(Stmt::Let {
                    local: Some(local),
                    init: value,
                    span,
                })
            }
            other => Err(Error::new(
                other.span(),
                "only `let name`, `let mut name` and `let _` patterns are supported",
            )),
        }
    }

    fn expr_stmt(&mut self, e: &syn::Expr, semi: bool, tail: bool) -> Result<Stmt> {
        let span = e.span();
        if let syn::Expr::Call(c) = e
            && let syn::Expr::Path(p) = &*c.func
            && p.path.is_ident("discard")
        {
            if !c.args.is_empty() {
                return Err(Error::new(c.args.span(), "`discard()` takes no arguments"));
            }
            if self.non_fragment_entry {
                return Err(Error::new(
                    span,
                    "`discard()` ends a fragment invocation; it is allowed only in fragment entry \
                     points and the helpers they call",
                ));
            }
            return Ok(Stmt::Discard(span));
        }
        match e {
            syn::Expr::Assign(a) => {
                let place = self.expr(&a.left)?;
                self.check_place(&place, true)?;
                let value = self.expr_as(&a.right, &place.ty)?;
                Ok(Stmt::Assign {
                    place,
                    op: None,
                    value,
                    span,
                })
            }
            syn::Expr::Binary(b) if compound_op(&b.op).is_some() => {
                #[expect(clippy::expect_used, reason = "the match guard checked it")]
                let op = compound_op(&b.op).expect("checked");
                let place = self.expr(&b.left)?;
                self.check_place(&place, true)?;
                let value = self.expr(&b.right)?;
                let result = self.binary(op, place.clone(), value.clone(), b.op.span())?;
                if result.ty != place.ty {
                    return Err(self.err_mismatch(&place.ty, &result));
                }
                Ok(match result.kind {
                    ExprKind::Binary(o, _, r) if o == op => Stmt::Assign {
                        place,
                        op: Some(op),
                        value: *r,
                        span,
                    },
                    // Lowered to another operator (`b ^= c` on `bool` is `b = b != c`): WGSL
                    // has no compound form of it.
                    _ => Stmt::Assign {
                        place,
                        op: None,
                        value: result,
                        span,
                    },
                })
            }
            syn::Expr::If(i) => self.if_stmt(i),
            syn::Expr::ForLoop(f) => {
                if let Some(l) = &f.label {
                    return Err(Error::new(l.span(), "loop labels are not supported"));
                }
                let syn::Expr::Range(r) = &*f.expr else {
                    return Err(Error::new(
                        f.expr.span(),
                        "`for` loops iterate over ranges only: `for i in start..end`",
                    ));
                };
                let (Some(start), Some(end)) = (&r.start, &r.end) else {
                    return Err(Error::new(r.span(), "`for` ranges need a start and an end"));
                };
                let start = self.expr(start)?;
                let mut end = self.expr(end)?;
                let ty = start
                    .ty
                    .unify(&end.ty)
                    .filter(|t| matches!(t, Ty::Scalar(s) if s.is_int32()))
                    .ok_or_else(|| {
                        Error::new(
                            r.span(),
                            format!(
                                "range bounds must be `u32` or `i32` integers of one type, found `{}` and `{}`",
                                self.ty_name(&start.ty),
                                self.ty_name(&end.ty)
                            ),
                        )
                    })?
                    .concretize();
                let syn::Pat::Ident(pi) = &*f.pat else {
                    return Err(Error::new(
                        f.pat.span(),
                        "the loop variable must be a plain name",
                    ));
                };
                self.push_scope();
                let var = self.declare(&pi.ident.to_string(), ty.clone(), false, pi.ident.span());
                self.loop_depth += 1;
                let body = self.block(&f.body);
                self.loop_depth -= 1;
                self.pop_scope();
                let inclusive = matches!(r.limits, syn::RangeLimits::Closed(_));
                // Rust evaluates the end once; WGSL's `for` condition re-evaluates it every
                // iteration. An end the body could change is read into a local first.
                let hoisted = (!self.loop_invariant(&end)).then(|| {
                    let l = self.hidden_local(&format!("{}_end", pi.ident), ty.clone(), end.span);
                    let span = end.span;
                    let init = std::mem::replace(
                        &mut end,
                        Expr {
                            kind: ExprKind::Local(l),
                            ty: ty.clone(),
                            span,
                        },
                    );
                    Stmt::Let {
                        local: Some(l),
                        init,
                        span,
                    }
                });
                let for_stmt = Stmt::For {
                    var,
                    start,
                    end,
                    inclusive,
                    body: body?,
                    span: f.for_token.span,
                };
                Ok(match hoisted {
                    Some(end_let) => Stmt::Block(vec![end_let, for_stmt]),
                    None => for_stmt,
                })
            }
            syn::Expr::While(w) => {
                if let Some(l) = &w.label {
                    return Err(Error::new(l.span(), "loop labels are not supported"));
                }
                if let syn::Expr::Let(l) = &*w.cond {
                    return Err(Error::new(l.span(), "`while let` is not supported"));
                }
                let cond = self.expr_as(&w.cond, &Ty::BOOL)?;
                self.loop_depth += 1;
                let body = self.block(&w.body);
                self.loop_depth -= 1;
                Ok(Stmt::While {
                    cond,
                    body: body?,
                    span: w.while_token.span,
                })
            }
            syn::Expr::Loop(l) => {
                if let Some(lb) = &l.label {
                    return Err(Error::new(lb.span(), "loop labels are not supported"));
                }
                self.loop_depth += 1;
                let body = self.block(&l.body);
                self.loop_depth -= 1;
                Ok(Stmt::Loop {
                    body: body?,
                    span: l.loop_token.span,
                })
            }
            syn::Expr::Break(b) => {
                if b.label.is_some() || b.expr.is_some() {
                    return Err(Error::new(
                        span,
                        "`break` takes no label or value in shader code",
                    ));
                }
                if self.loop_depth == 0 {
                    return Err(Error::new(span, "`break` outside of a loop"));
                }
                Ok(Stmt::Break(span))
            }
            syn::Expr::Continue(c) => {
                if c.label.is_some() {
                    return Err(Error::new(span, "loop labels are not supported"));
                }
                if self.loop_depth == 0 {
                    return Err(Error::new(span, "`continue` outside of a loop"));
                }
                Ok(Stmt::Continue(span))
            }
            syn::Expr::Return(r) => self.ret_stmt(r.expr.as_deref(), span),
            syn::Expr::Block(b) => {
                if let Some(l) = &b.label {
                    return Err(Error::new(l.span(), "block labels are not supported"));
                }
                Ok(Stmt::Block(self.block(&b.block)?))
            }
            _ if tail => self.ret_stmt(Some(e), span),
            _ => {
                let x = self.expr(e)?;
                if !semi && x.ty != Ty::Unit {
                    return Err(Error::new(
                        span,
                        "only a function's last expression can produce its value; add `;` or `return`",
                    ));
                }
                Ok(Stmt::Expr(x))
            }
        }
    }

    fn ret_stmt(&mut self, e: Option<&syn::Expr>, span: proc_macro2::Span) -> Result<Stmt> {
        let ret = self.ret.clone();
        match e {
            None if ret == Ty::Unit => Ok(Stmt::Return(None, span)),
            None => Err(Error::new(
                span,
                format!(
                    "this function returns `{}`; `return` needs a value",
                    self.ty_name(&ret)
                ),
            )),
            Some(e) if ret == Ty::Unit => {
                let x = self.expr(e)?;
                if x.ty == Ty::Unit {
                    return Ok(Stmt::Expr(x));
                }
                Err(Error::new(
                    x.span,
                    "this function returns nothing; remove the value or declare a return type",
                ))
            }
            Some(e) => Ok(Stmt::Return(Some(self.expr_as(e, &ret)?), span)),
        }
    }

    fn if_stmt(&mut self, i: &syn::ExprIf) -> Result<Stmt> {
        if let syn::Expr::Let(l) = &*i.cond {
            return Err(Error::new(l.span(), "`if let` is not supported"));
        }
        let cond = self.expr_as(&i.cond, &Ty::BOOL)?;
        let then = self.block(&i.then_branch)?;
        let els = match &i.else_branch {
            None => None,
            Some((_, e)) => match &**e {
                syn::Expr::If(inner) => Some(vec![self.if_stmt(inner)?]),
                syn::Expr::Block(b) => Some(self.block(&b.block)?),
                other => return Err(Error::new(other.span(), "expected a block after `else`")),
            },
        };
        Ok(Stmt::If {
            cond,
            then,
            els,
            span: i.if_token.span,
        })
    }
}
