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
        let mut slot = match root {
            Root::Local(l) => frame.get_mut(l).ok_or(EvalError::UnknownLocal(l))?,
            Root::Global(g) => self.global_mut(g)?,
        };
        for index in path {
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
        *slot = v;
        Ok(())
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
