//! Expression and literal printing. Axis-dependent constant subexpressions are folded to the
//! variant's literal; operands that are operations get parentheses (WGSL forbids mixing some
//! operators without them), so the output never depends on precedence subtleties.

use super::writer::Writer;
use crate::ir::{BinOp, Expr, ExprKind, Lit, Scalar, Ty, UnOp};
use crate::variants::eval;
use std::fmt::Write;

fn float_text(v: f64) -> String {
    let s = format!("{v:?}");
    if s.contains(['.', 'e', 'E']) || s.contains("inf") || s.contains("NaN") {
        s
    } else {
        format!("{s}.0")
    }
}

fn f32_text(v: f32) -> String {
    let s = format!("{v:?}");
    if s.contains(['.', 'e', 'E']) {
        s
    } else {
        format!("{s}.0")
    }
}

/// Prints a literal of the given scalar type.
pub(crate) fn lit_text(l: Lit) -> String {
    match l {
        Lit::Bool(b) => b.to_string(),
        Lit::Int(v, Scalar::U32) => format!("{}u", v as u32),
        Lit::Int(v, Scalar::I32) if v == i128::from(i32::MIN) => "i32(-2147483648)".into(),
        Lit::Int(v, Scalar::I32) => format!("{v}i"),
        Lit::Int(v, Scalar::U64) => format!("{}lu", v as u64),
        Lit::Int(v, Scalar::F32) => format!("{}f", float_text(v as f32 as f64)),
        Lit::Int(v, _) => v.to_string(),
        Lit::Float(v, Scalar::F32) => format!("{}f", f32_text(v as f32)),
        Lit::Float(v, _) => float_text(v),
    }
}

impl Writer<'_> {
    pub(super) fn needs_parens(e: &Expr) -> bool {
        matches!(
            e.kind,
            ExprKind::Binary(..) | ExprKind::Unary(..) | ExprKind::Deref(_) | ExprKind::AddrOf(_)
        ) || matches!(e.kind, ExprKind::Lit(Lit::Int(v, _)) if v < 0)
            || matches!(e.kind, ExprKind::Lit(Lit::Float(v, _)) if v < 0.0)
    }

    pub(super) fn operand(&mut self, e: &Expr) {
        let folded = self.folded(e);
        if Self::needs_parens(e) && folded.is_none() {
            self.out.push('(');
            self.expr(e);
            self.out.push(')');
        } else {
            self.expr(e);
        }
    }

    /// Whether `e` is a constant of this variant (a literal, or folds to one): naga checks
    /// constant shift amounts itself.
    pub(super) fn is_constant(&self, e: &Expr) -> bool {
        matches!(
            e.kind,
            ExprKind::Lit(_) | ExprKind::Const(_) | ExprKind::Axis(_)
        ) || eval(e, self.m, self.env).is_some()
    }

    /// The literal an axis-dependent constant subexpression folds to, if any, and the literal
    /// of a constant operator or conversion on a `u64`: naga's constant evaluator has no
    /// `u64` operators, and converts a constant `u64` to no 32-bit type (a function would
    /// leave such an operator to run time, a module-scope `const` cannot).
    pub(super) fn folded(&self, e: &Expr) -> Option<Lit> {
        let u64_operand = match &e.kind {
            ExprKind::Unary(_, x) | ExprKind::Cast(x) => x.ty == Ty::U64,
            ExprKind::Binary(_, a, b) => a.ty == Ty::U64 || b.ty == Ty::U64,
            _ => return None,
        };
        if !u64_operand && !crate::front::mentions_axis(e, self.m) {
            return None;
        }
        eval(e, self.m, self.env).map(|v| v.to_lit(&e.ty))
    }

    pub(super) fn args(&mut self, args: &[Expr], pointer_first: bool) {
        for (i, a) in args.iter().enumerate() {
            if i > 0 {
                self.out.push_str(", ");
            }
            if i == 0 && pointer_first {
                self.out.push('&');
            }
            self.list_item(a);
        }
    }

    /// An element of a comma-separated list (call, builtin and constructor arguments, array
    /// literals). WGSL's template-list discovery reads `f(a < b, c > d)` as `f(a<b, c>d)`, a
    /// template `a<..>`: an identifier then `<`, closed by a later `>` (or `>>`) with only
    /// commas and expressions between. Comparisons and shifts are therefore parenthesised in
    /// list positions (`f((a < b), (c > d))`); elsewhere they already are whenever they are
    /// operands.
    fn list_item(&mut self, e: &Expr) {
        let ambiguous = matches!(
            e.kind,
            ExprKind::Binary(
                BinOp::Lt | BinOp::Gt | BinOp::Le | BinOp::Ge | BinOp::Shl | BinOp::Shr,
                ..
            )
        ) && self.folded(e).is_none();
        if ambiguous {
            self.out.push('(');
            self.expr(e);
            self.out.push(')');
        } else {
            self.expr(e);
        }
    }

    /// Prints a literal, noting a 64-bit one.
    pub(super) fn lit(&mut self, l: Lit) {
        if matches!(l, Lit::Int(_, Scalar::U64)) {
            self.int64.set(true);
        }
        self.out.push_str(&lit_text(l));
    }

    pub(super) fn expr(&mut self, e: &Expr) {
        let start = self.out.len();
        if let Some(l) = self.folded(e) {
            self.lit(l);
            self.map.record(start..self.out.len(), e.span);
            return;
        }
        match &e.kind {
            ExprKind::Lit(l) => self.lit(*l),
            ExprKind::Local(l) => {
                let name = self.locals[*l].name.clone();
                self.out.push_str(&name);
            }
            ExprKind::Global(g) => self.out.push_str(&self.m.globals[*g].name),
            ExprKind::Const(c) => self.out.push_str(&self.m.consts[*c].name),
            ExprKind::Axis(a) => self.lit(self.env.values[*a]),
            ExprKind::Unary(op, x) => {
                self.out.push_str(match op {
                    UnOp::Neg => "-",
                    UnOp::Not => "!",
                    UnOp::BitNot => "~",
                });
                self.operand(x);
            }
            ExprKind::Binary(op @ (BinOp::Shl | BinOp::Shr), a, b) if !self.is_constant(b) => {
                self.operand(a);
                let _ = write!(self.out, " {} ", op.symbol());
                self.shift_amount(&a.ty, b);
            }
            ExprKind::Binary(op, a, b) => {
                self.operand(a);
                let _ = write!(self.out, " {} ", op.symbol());
                self.operand(b);
            }
            // `i32 as u64` sign-extends, as in Rust: through `i64`, since naga's SPIR-V writes
            // `u64(i32)` as a zero-extending `UConvert` (and its constant evaluator
            // sign-extends).
            ExprKind::Cast(x) if e.ty == Ty::U64 && x.ty.scalar() == Some(Scalar::I32) => {
                let t = self.ty(&e.ty);
                let _ = write!(self.out, "{t}(i64(");
                self.expr(x);
                self.out.push_str("))");
            }
            ExprKind::Cast(x) => {
                let t = self.ty(&e.ty);
                let _ = write!(self.out, "{t}(");
                self.expr(x);
                self.out.push(')');
            }
            ExprKind::Field(b, i) => {
                self.operand(b);
                let Ty::Struct(id) = b.ty else {
                    unreachable!("field of a struct")
                };
                let _ = write!(self.out, ".{}", self.m.structs[id].fields[*i].name);
            }
            ExprKind::Swizzle(b, s) => {
                self.operand(b);
                let _ = write!(self.out, ".{s}");
            }
            ExprKind::Index(b, i) => {
                self.operand(b);
                self.out.push('[');
                self.expr(i);
                self.out.push(']');
            }
            ExprKind::Construct(args) => {
                let t = self.ty(&e.ty);
                let _ = write!(self.out, "{t}(");
                self.args(args, false);
                self.out.push(')');
            }
            ExprKind::Call(f, args) => {
                let _ = write!(self.out, "{}(", self.m.functions[*f].name);
                self.args(args, false);
                self.out.push(')');
            }
            // `i32` abs through a helper (see `int_abs_helpers`); constants fold in naga.
            ExprKind::Builtin(b, args)
                if b.wgsl == "abs"
                    && e.ty.scalar() == Some(Scalar::I32)
                    && !self.is_constant(&args[0]) =>
            {
                let n = match e.ty {
                    Ty::Vector(n, _) => n,
                    _ => 1,
                };
                self.int_abs.insert(n);
                let _ = write!(self.out, "{}(", super::writer::int_abs_names(n).0);
                self.args(args, false);
                self.out.push(')');
            }
            ExprKind::Builtin(b, args) => {
                let _ = write!(self.out, "{}(", b.wgsl);
                self.args(args, b.pointer_first);
                self.out.push(')');
            }
            ExprKind::AddrOf(x) => {
                self.out.push('&');
                self.operand(x);
            }
            ExprKind::Deref(x) => {
                self.out.push('*');
                self.operand(x);
            }
        }
        self.map.record(start..self.out.len(), e.span);
    }

    /// A runtime shift amount, masked: WGSL takes it modulo the bit width of the shifted
    /// value `base` (32, or 64 for `u64`), but SPIR-V leaves amounts of the width or more
    /// undefined (the guide's "Semantics"). Also for `<<=` and `>>=`.
    pub(super) fn shift_amount(&mut self, base: &Ty, b: &Expr) {
        self.out.push('(');
        self.operand(b);
        match b.ty {
            Ty::Vector(n, _) => {
                let _ = write!(self.out, " & vec{n}<u32>(31u))");
            }
            _ if *base == Ty::U64 => self.out.push_str(" & 63u)"),
            _ => self.out.push_str(" & 31u)"),
        }
    }
}
