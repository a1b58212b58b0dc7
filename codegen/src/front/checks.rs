//! Whole-module checks after lowering: recursion, how structs are used (uniform, storage,
//! entry point IO) and the rules that follow, and entry point locations.

use super::ctx::ModCtx;
use super::signature::check_builtin_type;
use crate::ir::{Expr, ExprKind, Io, Module, Space, Stage, StructUse, Ty};
use proc_macro2::Span;
use std::collections::HashMap;
use syn::{Error, Result};

pub(crate) fn check_module(m: &mut ModCtx) -> Result<()> {
    check_recursion(m)?;
    mark_struct_uses(m)?;
    check_structs(m)?;
    check_locations(&m.module)?;
    Ok(())
}

fn check_recursion(m: &ModCtx) -> Result<()> {
    // 0 = unvisited, 1 = on stack, 2 = done
    fn visit(f: usize, m: &ModCtx, state: &mut [u8], stack: &mut Vec<usize>) -> Result<()> {
        state[f] = 1;
        stack.push(f);
        for &(callee, span) in &m.calls[f] {
            if state[callee] == 1 {
                let names = &m.module.functions;
                let start = stack.iter().position(|&x| x == callee).unwrap_or(0);
                let mut chain: Vec<&str> = stack[start..]
                    .iter()
                    .map(|&i| names[i].name.as_str())
                    .collect();
                chain.push(&names[callee].name);
                return Err(Error::new(
                    span,
                    format!(
                        "recursion is not supported on the GPU: {}; rewrite it as a loop",
                        chain.join(" -> ")
                    ),
                ));
            }
            if state[callee] == 0 {
                visit(callee, m, state, stack)?;
            }
        }
        stack.pop();
        state[f] = 2;
        Ok(())
    }
    let mut state = vec![0u8; m.module.functions.len()];
    for f in 0..state.len() {
        if state[f] == 0 {
            visit(f, m, &mut state, &mut vec![])?;
        }
    }
    Ok(())
}

fn mark(ty: &Ty, m: &mut Module, set: &dyn Fn(&mut StructUse)) {
    match ty {
        Ty::Struct(id) => {
            set(&mut m.structs[*id].uses);
            let fields: Vec<Ty> = m.structs[*id].fields.iter().map(|f| f.ty.clone()).collect();
            for f in &fields {
                mark(f, m, set);
            }
        }
        Ty::Array(t, _) | Ty::RuntimeArray(t) => mark(t, m, set),
        _ => {}
    }
}

fn mark_struct_uses(m: &mut ModCtx) -> Result<()> {
    let module = &mut m.module;
    let globals: Vec<(Ty, Space)> = module
        .globals
        .iter()
        .map(|g| (g.ty.clone(), g.space))
        .collect();
    for (ty, space) in &globals {
        match space {
            Space::Uniform => mark(ty, module, &|u| u.uniform = true),
            Space::Storage { .. } => mark(ty, module, &|u| u.storage = true),
            _ => {}
        }
    }
    let mut io_types = vec![];
    for f in &module.functions {
        if f.stage.is_some() {
            for p in &f.params {
                io_types.push(f.locals[p.local].ty.clone());
            }
            io_types.push(f.ret.clone());
        }
    }
    for t in &io_types {
        if let Ty::Struct(id) = t {
            module.structs[*id].uses.io = true;
        }
    }
    Ok(())
}

/// Whether an expression depends on an axis (directly or through a `const`).
pub(crate) fn mentions_axis(e: &Expr, m: &Module) -> bool {
    match &e.kind {
        ExprKind::Axis(_) => true,
        ExprKind::Const(c) => mentions_axis(&m.consts[*c].value, m),
        ExprKind::Unary(_, x) | ExprKind::Cast(x) => mentions_axis(x, m),
        ExprKind::Binary(_, a, b) => mentions_axis(a, m) || mentions_axis(b, m),
        _ => false,
    }
}

fn ty_axis_span(ty: &Ty, m: &Module) -> Option<Span> {
    match ty {
        Ty::Array(t, len) => {
            if mentions_axis(&len.0, m) {
                Some(len.0.span)
            } else {
                ty_axis_span(t, m)
            }
        }
        _ => None,
    }
}

fn check_structs(m: &ModCtx) -> Result<()> {
    let module = &m.module;
    let cx = super::ctx::FnCtx::new(m, true);
    for s in &module.structs {
        for f in &s.fields {
            if let Some(span) = ty_axis_span(&f.ty, module) {
                return Err(Error::new(
                    span,
                    "struct layouts cannot depend on axes (the host type is shared by all variants); size the array with a constant, or use a workgroup array",
                ));
            }
            if (s.uses.uniform || s.uses.storage) && super::statics::vec3_array(&f.ty) {
                return Err(Error::new(f.span, super::statics::VEC3_ARRAY));
            }
            if s.uses.uniform
                && let Some(stride) = uniform_bad_stride(&f.ty, module)
            {
                return Err(Error::new(
                    f.span,
                    format!(
                        "`{}` is used in a uniform buffer, where array elements must be 16-byte strided; this array's stride is {stride} bytes: use `[Vec4; N]`/`[UVec4; N]`, or a storage buffer",
                        s.name
                    ),
                ));
            }
            let buffer = s.uses.uniform || s.uses.storage;
            if buffer && f.io.is_some() {
                return Err(Error::new(
                    f.span,
                    format!(
                        "`{}` is used in a buffer, so its fields cannot have `#[location]`/`#[builtin]`; use separate IO and buffer structs",
                        s.name
                    ),
                ));
            }
            if buffer && contains_bool(&f.ty, module) {
                return Err(Error::new(
                    f.span,
                    format!(
                        "`bool` cannot be stored in buffers (`{}` is used in a buffer); use `u32`",
                        s.name
                    ),
                ));
            }
            if s.uses.io {
                match &f.io {
                    None => {
                        return Err(Error::new(
                            f.span,
                            format!(
                                "fields of the entry point IO struct `{}` need `#[location(N)]` or `#[builtin(..)]`",
                                s.name
                            ),
                        ));
                    }
                    Some(io @ (Io::Builtin(_) | Io::InvariantPosition)) => {
                        check_builtin_type(&cx, io.builtin().unwrap_or_default(), &f.ty, f.span)?
                    }
                    Some(Io::Location { .. }) => {
                        if f.ty == Ty::U64 {
                            return Err(Error::new(f.span, super::build::U64_LOCATION));
                        }
                        if !f.ty.is_numeric() {
                            return Err(Error::new(
                                f.span,
                                "`#[location]` fields must be numeric scalars or vectors",
                            ));
                        }
                    }
                }
            } else if f.io.is_some() && !library_io_struct(m, &s.name) {
                return Err(Error::new(
                    f.span,
                    format!(
                        "`#[location]`/`#[builtin]` only make sense on entry point IO structs, and `{}` is not used as one",
                        s.name
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Whether IO attributes on struct `name` are for other modules' entry points: a library's own
/// struct (a library has none), or one merged in from a library, which the modules that use it
/// may or may not take as IO.
fn library_io_struct(m: &ModCtx, name: &str) -> bool {
    m.module.library || m.origins.get(name).is_some_and(Option::is_some)
}

/// The element stride of an array type that breaks the uniform 16-byte stride rule.
fn uniform_bad_stride(ty: &Ty, m: &Module) -> Option<u32> {
    let Ty::Array(elem, _) = ty else { return None };
    let env = crate::variants::Env { values: vec![] };
    let l = crate::layout::layout_of(elem, m, &env);
    let stride = crate::layout::round_up(l.size, l.align);
    (!stride.is_multiple_of(16)).then_some(stride)
}

fn contains_bool(ty: &Ty, m: &Module) -> bool {
    match ty {
        Ty::Scalar(crate::ir::Scalar::Bool) | Ty::Vector(_, crate::ir::Scalar::Bool) => true,
        Ty::Array(t, _) | Ty::RuntimeArray(t) => contains_bool(t, m),
        Ty::Struct(id) => m.structs[*id]
            .fields
            .iter()
            .any(|f| contains_bool(&f.ty, m)),
        _ => false,
    }
}

fn check_locations(m: &Module) -> Result<()> {
    for f in &m.functions {
        let Some(stage) = &f.stage else { continue };
        let mut inputs: HashMap<u32, ()> = HashMap::new();
        let add = |set: &mut HashMap<u32, ()>, io: &Io, span: Span, dir: &str| -> Result<()> {
            if let Io::Location { location, .. } = io
                && set.insert(*location, ()).is_some()
            {
                return Err(Error::new(
                    span,
                    format!(
                        "duplicate {dir} `#[location({location})]` in entry point `{}`",
                        f.name
                    ),
                ));
            }
            Ok(())
        };
        for p in &f.params {
            let local = &f.locals[p.local];
            if matches!(stage, Stage::Compute(_)) && matches!(p.io, Some(Io::Location { .. })) {
                return Err(Error::new(
                    local.span,
                    "compute entry points have no `#[location]` inputs",
                ));
            }
            match (&p.io, &local.ty) {
                (Some(io), _) => add(&mut inputs, io, local.span, "input")?,
                (None, Ty::Struct(id)) => {
                    for fld in &m.structs[*id].fields {
                        if let Some(io) = &fld.io {
                            add(&mut inputs, io, fld.span, "input")?;
                        }
                    }
                }
                _ => {}
            }
        }
        let mut outputs = HashMap::new();
        if let Ty::Struct(id) = &f.ret {
            for fld in &m.structs[*id].fields {
                if let Some(io) = &fld.io {
                    add(&mut outputs, io, fld.span, "output")?;
                }
            }
        }
    }
    Ok(())
}
