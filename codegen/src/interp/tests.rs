//! Edge cases of the evaluator's semantics, and one module compiled from source.

use super::*;
use crate::ir::{BinOp, Builtin, ExprKind, Scalar, Ty, UnOp};
use proc_macro2::Span;

fn module() -> Module {
    Module {
        name: "t".into(),
        span: Span::call_site(),
        axes: vec![],
        excludes: vec![],
        requires_subgroup: None,
        structs: vec![],
        consts: vec![],
        globals: vec![],
        functions: vec![],
        library: false,
    }
}

fn ex(kind: ExprKind, ty: Ty) -> Expr {
    Expr {
        kind,
        ty,
        span: Span::call_site(),
    }
}

fn local(i: usize, ty: Ty) -> Expr {
    ex(ExprKind::Local(i), ty)
}

fn eval(e: &Expr, locals: &[Value]) -> Result<Value, EvalError> {
    eval_expr(&module(), &Env { values: vec![] }, e, locals)
}

fn bin(op: BinOp, ty: Ty, a: Value, b: Value) -> Value {
    let aty = Ty::Scalar(a.scalar().expect("scalar"));
    let bty = Ty::Scalar(b.scalar().expect("scalar"));
    let e = ex(
        ExprKind::Binary(op, Box::new(local(0, aty)), Box::new(local(1, bty))),
        ty,
    );
    eval(&e, &[a, b]).expect("evaluates")
}

#[test]
fn integer_arithmetic_wraps() {
    use Value::*;
    assert_eq!(
        bin(BinOp::Add, Ty::I32, I32(i32::MAX), I32(1)),
        I32(i32::MIN)
    );
    assert_eq!(bin(BinOp::Sub, Ty::U32, U32(0), U32(1)), U32(u32::MAX));
    assert_eq!(bin(BinOp::Mul, Ty::I32, I32(0x10000), I32(0x10000)), I32(0));
    let neg = ex(
        ExprKind::Unary(UnOp::Neg, Box::new(local(0, Ty::I32))),
        Ty::I32,
    );
    assert_eq!(eval(&neg, &[I32(i32::MIN)]), Ok(I32(i32::MIN)));
}

#[test]
fn division_by_zero_and_min_by_minus_one() {
    use Value::*;
    assert_eq!(bin(BinOp::Div, Ty::I32, I32(7), I32(0)), I32(7));
    assert_eq!(bin(BinOp::Rem, Ty::I32, I32(7), I32(0)), I32(0));
    assert_eq!(bin(BinOp::Div, Ty::U32, U32(7), U32(0)), U32(7));
    assert_eq!(bin(BinOp::Rem, Ty::U32, U32(7), U32(0)), U32(0));
    assert_eq!(
        bin(BinOp::Div, Ty::I32, I32(i32::MIN), I32(-1)),
        I32(i32::MIN)
    );
    assert_eq!(bin(BinOp::Rem, Ty::I32, I32(i32::MIN), I32(-1)), I32(0));
    // Truncating division; the remainder has the dividend's sign.
    assert_eq!(bin(BinOp::Div, Ty::I32, I32(-7), I32(2)), I32(-3));
    assert_eq!(bin(BinOp::Rem, Ty::I32, I32(-7), I32(2)), I32(-1));
    assert_eq!(bin(BinOp::Rem, Ty::F32, F32(-7.5), F32(2.0)), F32(-1.5));
}

#[test]
fn shift_amounts_use_the_low_five_bits() {
    use Value::*;
    assert_eq!(bin(BinOp::Shl, Ty::U32, U32(1), U32(33)), U32(2));
    assert_eq!(bin(BinOp::Shl, Ty::U32, U32(1), U32(32)), U32(1));
    assert_eq!(bin(BinOp::Shr, Ty::I32, I32(-8), U32(1)), I32(-4));
    assert_eq!(bin(BinOp::Shr, Ty::I32, I32(-8), U32(65)), I32(-4));
    assert_eq!(bin(BinOp::Shr, Ty::U32, U32(0x8000_0000), U32(31)), U32(1));
    assert_eq!(bin(BinOp::Shl, Ty::I32, I32(1), U32(31)), I32(i32::MIN));
}

#[test]
fn float_to_int_casts_saturate_and_nan_is_zero() {
    use Value::*;
    let c = |v: f32, to: Scalar| ops::cast(&F32(v), to).expect("cast");
    assert_eq!(c(3.9, Scalar::I32), I32(3));
    assert_eq!(c(-3.9, Scalar::I32), I32(-3));
    assert_eq!(c(1e10, Scalar::I32), I32(2_147_483_520));
    assert_eq!(c(-1e10, Scalar::I32), I32(i32::MIN));
    assert_eq!(c(f32::INFINITY, Scalar::U32), U32(4_294_967_040));
    assert_eq!(c(-5.0, Scalar::U32), U32(0));
    assert_eq!(c(f32::NAN, Scalar::I32), I32(0));
    assert_eq!(c(f32::NAN, Scalar::U32), U32(0));
    assert_eq!(ops::cast(&I32(-1), Scalar::U32), Ok(U32(u32::MAX)));
    assert_eq!(ops::cast(&Bool(true), Scalar::U32), Ok(U32(1)));
}

#[test]
fn builtins_follow_wgsl() {
    use Value::*;
    let call = |n: &str, a: &[Value]| builtins::call(n, a).expect("builtin");
    assert_eq!(call("abs", &[I32(i32::MIN)]), I32(i32::MIN));
    assert_eq!(call("sign", &[F32(0.0)]), F32(0.0));
    assert_eq!(call("round", &[F32(2.5)]), F32(2.0));
    assert_eq!(call("round", &[F32(-0.5)]), F32(-0.0));
    assert_eq!(call("fract", &[F32(-0.25)]), F32(0.75));
    assert_eq!(call("countLeadingZeros", &[U32(0)]), U32(32));
    assert_eq!(call("countTrailingZeros", &[I32(0)]), I32(32));
    assert_eq!(call("countOneBits", &[I32(-1)]), I32(32));
    assert_eq!(call("reverseBits", &[U32(1)]), U32(0x8000_0000));
    assert_eq!(call("clamp", &[I32(5), I32(3), I32(1)]), I32(1));
    assert_eq!(call("step", &[F32(1.0), F32(1.0)]), F32(1.0));
    assert_eq!(call("select", &[U32(1), U32(2), Bool(true)]), U32(2));
    let v = |a: f32, b: f32| Vector(vec![F32(a), F32(b)]);
    assert_eq!(call("dot", &[v(1.0, 2.0), v(3.0, 4.0)]), F32(11.0));
    assert_eq!(call("length", &[v(3.0, 4.0)]), F32(5.0));
    assert_eq!(call("max", &[v(1.0, 5.0), v(3.0, 4.0)]), v(3.0, 5.0));
    assert!(matches!(
        builtins::call("textureLoad", &[]),
        Err(EvalError::Unsupported(_))
    ));
}

#[test]
fn short_circuit_skips_the_right_operand() {
    // `false && <unknown local>` never reads local 1.
    let e = ex(
        ExprKind::Binary(
            BinOp::And,
            Box::new(local(0, Ty::BOOL)),
            Box::new(local(1, Ty::BOOL)),
        ),
        Ty::BOOL,
    );
    assert_eq!(eval(&e, &[Value::Bool(false)]), Ok(Value::Bool(false)));
    assert_eq!(
        eval(&e, &[Value::Bool(true)]),
        Err(EvalError::UnknownLocal(1))
    );
    // A subgroup operation needs the other lanes of a dispatch.
    let b = Builtin {
        wgsl: "subgroupAdd",
        subgroup: true,
        pointer_first: false,
    };
    let e = ex(ExprKind::Builtin(b, vec![local(0, Ty::U32)]), Ty::U32);
    assert!(matches!(
        eval(&e, &[Value::U32(1)]),
        Err(EvalError::Unsupported(_))
    ));
}

/// A kernel compiled from source: the evaluator reads the typed IR of its `let`s, with
/// abstract literals taking their context's type.
#[test]
fn evaluates_the_ir_of_a_compiled_kernel() {
    let src = r#"
        #[shader(axes(k: u32 = [3]))]
        mod m {
            const C: i32 = -2;
            #[storage(group = 0, binding = 0, read_write)]
            static OUT: [u32];
            #[compute(workgroup_size(1))]
            fn main(#[builtin(global_invocation_id)] gid: UVec3) {
                let a = gid.x + 1;
                let v = UVec3::new(a, 2u32, k) * 2 + UVec3::splat(a).zyx();
                let w = (v.as_ivec3() + C).as_vec3().xy() * 0.5;
                let s = select(w.x > 1.0, v[1] << (a + 28), 7u32 % (a - a));
                OUT[0] = s + (w.y as u32) + v.dot(UVec3::ONE);
            }
        }
    "#;
    let c = crate::compile_source(src).expect("compiles");
    let f = &c.module.functions[0];
    let env = &c.keys[0].env;
    let mut locals = vec![Value::Vector(vec![
        Value::U32(4),
        Value::U32(0),
        Value::U32(0),
    ])];
    locals.resize(f.locals.len(), Value::Bool(false));
    let mut last = None;
    for st in &f.body {
        match st {
            crate::ir::Stmt::Let {
                local: Some(l),
                init,
                ..
            } => {
                locals[*l] = eval_expr(&c.module, env, init, &locals).expect("let evaluates");
            }
            crate::ir::Stmt::Assign { value, .. } => {
                last = Some(eval_expr(&c.module, env, value, &locals).expect("evaluates"));
            }
            _ => {}
        }
    }
    // a = 5; v = (10, 4, 6) + (5, 5, 5) = (15, 9, 11); w = ((13, 7) * 0.5) = (6.5, 3.5);
    // s = 9 << 1 = 18; result = 18 + 3 + 35.
    assert_eq!(last, Some(Value::U32(56)));
}
