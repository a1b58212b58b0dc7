//! Statement printing: blocks, statements with their source-map entries, `for` loops whose
//! inclusive end may be the type's maximum, and `if` chains with constant branches pruned.

use super::writer::Writer;
use crate::ir::{BinOp, Block, Expr, ExprKind, Lit, Scalar, Stmt, Ty};
use crate::variants::{Branch, branch};
use proc_macro2::Span;
use std::fmt::Write;

impl<'a> Writer<'a> {
    pub(super) fn block_body(&mut self, b: &'a Block) {
        for s in b {
            self.stmt(s);
        }
    }

    fn braced(&mut self, b: &'a Block) {
        self.out.push_str("{\n");
        self.indent += 1;
        self.block_body(b);
        self.indent -= 1;
        self.line_start();
        self.out.push('}');
    }

    fn stmt(&mut self, s: &'a Stmt) {
        if let Stmt::If {
            cond, then, els, ..
        } = s
        {
            match branch(cond, self.m, self.env) {
                Branch::Then => return self.block_body(then),
                Branch::Else => {
                    if let Some(e) = els {
                        self.block_body(e);
                    }
                    return;
                }
                Branch::Dynamic => {}
            }
        }
        self.line_start();
        let start = self.out.len();
        let span = match s {
            Stmt::Let { local, init, span } => {
                match local {
                    Some(l) => {
                        let local = &self.locals[*l];
                        let kw = if local.mutable { "var" } else { "let" };
                        let _ = write!(self.out, "{kw} {}: {} = ", local.name, self.ty(&local.ty));
                    }
                    // `let _ = A.store(v);` and `let _ = V64.fetch_min(v);`: a call of type
                    // `()` is a bare statement (naga gives a phony assignment a result).
                    None if init.ty == Ty::Unit => {}
                    None => self.out.push_str("_ = "),
                }
                self.expr(init);
                self.out.push(';');
                *span
            }
            Stmt::Assign {
                place,
                op,
                value,
                span,
            } => {
                self.expr(place);
                let _ = write!(self.out, " {}= ", op.map_or("", |o| o.symbol()));
                match op {
                    Some(BinOp::Shl | BinOp::Shr) if !self.is_constant(value) => {
                        self.shift_amount(&place.ty, value);
                    }
                    _ => self.expr(value),
                }
                self.out.push(';');
                *span
            }
            Stmt::Expr(e) => {
                if e.ty != Ty::Unit {
                    self.out.push_str("_ = ");
                }
                self.expr(e);
                self.out.push(';');
                e.span
            }
            Stmt::If { .. } => self.if_chain(s),
            Stmt::For {
                var,
                start: from,
                end,
                inclusive,
                body,
                span,
            } => {
                if *inclusive && !below_max(end) {
                    self.inclusive_loop(*var, from, end, body);
                    return self.end_stmt(start, *span);
                }
                let local = &self.locals[*var];
                let _ = write!(
                    self.out,
                    "for (var {}: {} = ",
                    local.name,
                    self.ty(&local.ty)
                );
                self.expr(from);
                let _ = write!(
                    self.out,
                    "; {} {} ",
                    local.name,
                    if *inclusive { "<=" } else { "<" }
                );
                self.expr(end);
                let _ = write!(self.out, "; {}++) ", local.name);
                self.braced(body);
                *span
            }
            Stmt::While { cond, body, span } => {
                self.out.push_str("while ");
                self.expr(cond);
                self.out.push(' ');
                self.braced(body);
                *span
            }
            Stmt::Loop { body, span } => {
                self.out.push_str("loop ");
                self.braced(body);
                *span
            }
            Stmt::Break(span) => {
                self.out.push_str("break;");
                *span
            }
            Stmt::Continue(span) => {
                self.out.push_str("continue;");
                *span
            }
            Stmt::Discard(span) => {
                self.out.push_str("discard;");
                *span
            }
            Stmt::Return(e, span) => {
                self.out.push_str("return");
                if let Some(e) = e {
                    self.out.push(' ');
                    self.expr(e);
                }
                self.out.push(';');
                *span
            }
            Stmt::Block(b) => {
                self.braced(b);
                Span::call_site()
            }
        };
        self.end_stmt(start, span);
    }

    fn end_stmt(&mut self, start: usize, span: Span) {
        self.map.record(start..self.out.len(), span);
        self.out.push('\n');
    }

    /// `for i in a..=b` where `b` may be the type's maximum: WGSL's `i <= b; i++` would wrap
    /// and never end, so the last iteration is detected before the increment.
    fn inclusive_loop(&mut self, var: usize, from: &'a Expr, end: &'a Expr, body: &'a Block) {
        let name = self.locals[var].name.clone();
        let ty = self.ty(&self.locals[var].ty);
        self.out.push_str("{\n");
        self.indent += 1;
        self.line_start();
        let _ = write!(self.out, "var {name}: {ty} = ");
        self.expr(from);
        self.out.push_str(";\n");
        self.line_start();
        let _ = write!(self.out, "if {name} <= ");
        self.expr(end);
        self.out.push_str(" {\n");
        self.indent += 1;
        self.line_start();
        self.out.push_str("loop {\n");
        self.indent += 1;
        self.block_body(body);
        self.line_start();
        self.out.push_str("continuing {\n");
        self.indent += 1;
        self.line_start();
        let _ = write!(self.out, "let {name}_last = {name} == ");
        self.expr(end);
        self.out.push_str(";\n");
        self.line_start();
        let _ = writeln!(self.out, "{name}++;");
        self.line_start();
        let _ = writeln!(self.out, "break if {name}_last;");
        for _ in 0..3 {
            self.indent -= 1;
            self.line_start();
            self.out.push_str("}\n");
        }
        self.indent -= 1;
        self.line_start();
        self.out.push('}');
    }

    /// Prints a dynamic `if` and its `else if` chain; returns the span of the first `if`.
    fn if_chain(&mut self, s: &'a Stmt) -> Span {
        let Stmt::If {
            cond,
            then,
            els,
            span,
        } = s
        else {
            unreachable!("if_chain takes an if")
        };
        self.out.push_str("if ");
        self.expr(cond);
        self.out.push(' ');
        self.braced(then);
        if let Some(els) = els {
            if let [inner @ Stmt::If { cond: c2, .. }] = els.as_slice()
                && branch(c2, self.m, self.env) == Branch::Dynamic
            {
                self.out.push_str(" else ");
                self.if_chain(inner);
            } else if !self.prunes_to_empty(els) {
                self.out.push_str(" else ");
                self.braced(els);
            }
        }
        *span
    }

    fn prunes_to_empty(&self, b: &Block) -> bool {
        b.iter().all(|s| match s {
            Stmt::If {
                cond, then, els, ..
            } => match branch(cond, self.m, self.env) {
                Branch::Then => self.prunes_to_empty(then),
                Branch::Else => els.as_ref().is_none_or(|e| self.prunes_to_empty(e)),
                Branch::Dynamic => false,
            },
            _ => false,
        })
    }
}

/// Whether `end` is an integer literal below its type's maximum (`1..=4`), so that the
/// plain `for (..; i <= end; i++)` ends.
fn below_max(end: &Expr) -> bool {
    match (&end.kind, end.ty.scalar()) {
        (ExprKind::Lit(Lit::Int(v, _)), Some(Scalar::U32)) => *v < u32::MAX.into(),
        (ExprKind::Lit(Lit::Int(v, _)), Some(Scalar::U64)) => *v < u64::MAX.into(),
        (ExprKind::Lit(Lit::Int(v, _)), _) => *v < i32::MAX.into(),
        _ => false,
    }
}
