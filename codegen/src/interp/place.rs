//! Assignment targets: a local or a static, then a path of array elements, vector components
//! and struct fields, each index checked against the value it lands in.

use super::{EvalError, Machine, Value};
use crate::ir::{Expr, ExprKind};

/// Where a place starts.
enum Root {
    Local(usize),
    Global(usize),
}

impl Machine<'_> {
    /// Stores `v` into `place` (`x`, `v.y`, `a[i]`, `s.f[i].x`, `OUT[k]`).
    pub(crate) fn store(
        &mut self,
        frame: &mut [Value],
        place: &Expr,
        v: Value,
    ) -> Result<(), EvalError> {
        let mut path = vec![];
        let root = self.resolve(frame, place, &mut path)?;
        if let Root::Global(g) = root {
            self.track(g, &path, place.span, true)?;
        }
        let slot = match root {
            Root::Local(l) => frame.get_mut(l).ok_or(EvalError::UnknownLocal(l))?,
            Root::Global(g) => self.global_mut(g)?,
        };
        *walk_mut(slot, &path)? = v;
        Ok(())
    }

    /// Checks (and for a write, records) an access to workgroup memory for data races, when
    /// this machine runs in a dispatch that tracks them.
    pub(crate) fn track(
        &self,
        g: usize,
        path: &[i64],
        span: proc_macro2::Span,
        write: bool,
    ) -> Result<(), EvalError> {
        let Some((tracker, invocation)) = &self.race else {
            return Ok(());
        };
        let global = &self.module.globals[g];
        if global.space != crate::ir::Space::Workgroup {
            return Ok(());
        }
        let start = span.start();
        let access = super::race::Access {
            invocation: *invocation,
            line: start.line,
            column: start.column + 1,
            global: g,
            path,
            name: &global.name,
        };
        if write {
            tracker.borrow_mut().write(&access)
        } else {
            tracker.borrow().read(&access)
        }
    }

    /// Whether `e` is a static or an element, field or component of one.
    pub(crate) fn rooted_at_global(e: &Expr) -> bool {
        match &e.kind {
            ExprKind::Global(_) => true,
            ExprKind::Index(base, _) | ExprKind::Field(base, _) => Self::rooted_at_global(base),
            ExprKind::Swizzle(base, s) if s.len() == 1 => Self::rooted_at_global(base),
            _ => false,
        }
    }

    /// The value at a place inside a static (see [`Machine::rooted_at_global`]), copying only
    /// that value.
    pub(crate) fn read_global_place(
        &mut self,
        frame: &[Value],
        place: &Expr,
    ) -> Result<Value, EvalError> {
        let mut path = vec![];
        let Root::Global(g) = self.resolve(frame, place, &mut path)? else {
            return Err(EvalError::Type("a static place expected".into()));
        };
        self.track(g, &path, place.span, false)?;
        let mut slot = self.global(g)?;
        for &index in &path {
            let items = items_of(slot)?;
            slot = usize::try_from(index)
                .ok()
                .and_then(|k| items.get(k))
                .ok_or(EvalError::OutOfBounds {
                    index,
                    len: items.len(),
                })?;
        }
        Ok(slot.clone())
    }

    /// The value at a place inside a static, to modify in place (atomics).
    pub(crate) fn global_place_mut(
        &mut self,
        frame: &[Value],
        place: &Expr,
    ) -> Result<&mut Value, EvalError> {
        let mut path = vec![];
        let Root::Global(g) = self.resolve(frame, place, &mut path)? else {
            return Err(EvalError::Unsupported(
                "an atomic outside storage or workgroup memory".into(),
            ));
        };
        walk_mut(self.global_mut(g)?, &path)
    }

    /// The root of `place`, with the indices from it to the place pushed onto `path`.
    fn resolve(
        &mut self,
        frame: &[Value],
        place: &Expr,
        path: &mut Vec<i64>,
    ) -> Result<Root, EvalError> {
        match &place.kind {
            ExprKind::Local(l) => Ok(Root::Local(*l)),
            ExprKind::Global(g) => Ok(Root::Global(*g)),
            ExprKind::Index(base, index) => {
                let root = self.resolve(frame, base, path)?;
                let k = match self.eval(frame, index, None)? {
                    Value::I32(k) => k as i64,
                    Value::U32(k) => k as i64,
                    v => return Err(EvalError::Type(format!("index {v}"))),
                };
                path.push(k);
                Ok(root)
            }
            ExprKind::Field(base, i) => {
                let root = self.resolve(frame, base, path)?;
                path.push(*i as i64);
                Ok(root)
            }
            ExprKind::Swizzle(base, s) if s.len() == 1 => {
                let root = self.resolve(frame, base, path)?;
                path.push("xyzw".find(s.as_str()).unwrap_or(4) as i64);
                Ok(root)
            }
            ExprKind::Swizzle(_, s) => Err(EvalError::Unsupported(format!(
                "assigning to the swizzle `.{s}`"
            ))),
            ExprKind::Deref(_) | ExprKind::AddrOf(_) => {
                Err(EvalError::Unsupported("pointers".into()))
            }
            _ => Err(EvalError::Type(
                "assignment to a value that is not a place".into(),
            )),
        }
    }
}

fn items_of(v: &Value) -> Result<&[Value], EvalError> {
    match v {
        Value::Vector(items) | Value::Array(items) | Value::Struct(items) => Ok(items),
        other => Err(EvalError::Type(format!("indexing into {other}"))),
    }
}

/// The value `path` leads to from `slot`, each index checked.
fn walk_mut<'v>(mut slot: &'v mut Value, path: &[i64]) -> Result<&'v mut Value, EvalError> {
    for &index in path {
        let items = match slot {
            Value::Vector(items) | Value::Array(items) | Value::Struct(items) => items,
            other => return Err(EvalError::Type(format!("assigning into {other}"))),
        };
        let len = items.len();
        slot = usize::try_from(index)
            .ok()
            .and_then(|k| items.get_mut(k))
            .ok_or(EvalError::OutOfBounds { index, len })?;
    }
    Ok(slot)
}
