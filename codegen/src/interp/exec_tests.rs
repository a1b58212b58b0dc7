//! Statement execution on modules compiled from source: loops, places, calls, statics, the
//! step limit and error locations.

use super::{EvalError, Machine, Value};

/// Compiles a module whose helper functions the tests run, plus an entry point.
/// The entry point calls `f` so that the printed WGSL holds it.
fn module(helpers: &str) -> crate::Compiled {
    let src = format!(
        "#[shader] mod m {{\n{helpers}\n#[compute(workgroup_size(1, 1, 1))] fn main() {{ let _ = f(1u32); }}\n}}"
    );
    crate::compile_source(&src).unwrap_or_else(|e| panic!("{e}\n{src}"))
}

fn run(helpers: &str, f: &str, args: Vec<Value>) -> Result<Option<Value>, EvalError> {
    let c = module(helpers);
    Machine::new(&c.module, &c.keys[0].env).run(f, args)
}

#[test]
fn a_for_loop_reads_its_end_once() {
    let src = "fn f(k: u32) -> u32 {
        let mut n = k;
        let mut c = 0u32;
        for i in 0..n { n += 1; c += i; }
        c
    }";
    assert_eq!(run(src, "f", vec![Value::U32(4)]), Ok(Some(Value::U32(6))));
    // The printed WGSL reads the end into a local before the loop.
    let wgsl = &module(src).variants[0].wgsl;
    assert!(wgsl.contains("let i_end: u32 = n;"), "{wgsl}");
}

#[test]
fn an_inclusive_range_ends_at_the_types_maximum() {
    let src = "fn f(a: u32) -> u32 {
        let mut c = 0u32;
        for i in a..=u32::MAX { c += 1; if i == 5u32 { continue; } }
        c
    }";
    let max = u32::MAX;
    assert_eq!(
        run(src, "f", vec![Value::U32(max - 2)]),
        Ok(Some(Value::U32(3)))
    );
    assert_eq!(
        run(src, "f", vec![Value::U32(max)]),
        Ok(Some(Value::U32(1)))
    );
    let wgsl = &module(src).variants[0].wgsl;
    assert!(wgsl.contains("break if i_last;"), "{wgsl}");
}

#[test]
fn control_flow_and_places() {
    let src = "fn f(m: u32) -> i32 {
        let n = m as i32;
        let mut v = IVec3::new(1, 2, 3);
        let mut a = [10i32, 20, 30, 40];
        let mut k = 0;
        while k < n {
            k += 1;
            if k % 2 == 0 { continue; }
            v.y += k;
            a[(k % 4) as u32] <<= 1u32;
            let k = k * 100;
            v.z = k;
        }
        loop { if a[0] > 5 { a[0] -= 7; } else { break; } }
        v.x + v.y + v.z + a[0] + a[1] + a[2] + a[3]
    }";
    // k = 1, 3, 5: v.y = 2 + 9, a[1] and a[3] doubled (a[1] twice), v.z = 500; a[0] 10 -> 3.
    let want = 1 + 11 + 500 + 3 + 80 + 30 + 80;
    assert_eq!(
        run(src, "f", vec![Value::U32(5)]),
        Ok(Some(Value::I32(want)))
    );
}

#[test]
fn calls_return_early() {
    let src = "fn sign_of(x: i32) -> i32 { if x < 0 { return -1; } if x == 0 { return 0; } 1 }
               fn f(u: u32) -> i32 { let x = u as i32; sign_of(x) * 10 + sign_of(-x) }";
    assert_eq!(run(src, "f", vec![Value::U32(7)]), Ok(Some(Value::I32(9))));
    assert_eq!(run(src, "f", vec![Value::U32(0)]), Ok(Some(Value::I32(0))));
}

#[test]
fn statics_are_host_values() {
    let c = crate::compile_source(
        "#[shader] mod m {
            #[storage(group = 0, binding = 0)] static IN: [u32];
            #[storage(group = 0, binding = 1, read_write)] static OUT: [u32];
            #[compute(workgroup_size(1, 1, 1))]
            fn main(#[builtin(global_invocation_id)] gid: UVec3) {
                OUT[gid.x] = IN[gid.x] * 2u32 + IN.len();
            }
        }",
    )
    .expect("compiles");
    let mut m = Machine::new(&c.module, &c.keys[0].env);
    let words = |w: &[u32]| Value::Array(w.iter().map(|&x| Value::U32(x)).collect());
    m.set_global("IN", words(&[5, 6])).expect("IN exists");
    m.set_global("OUT", words(&[0, 0])).expect("OUT exists");
    let gid = |x| Value::Vector(vec![Value::U32(x), Value::U32(0), Value::U32(0)]);
    m.run("main", vec![gid(1)]).expect("runs");
    assert_eq!(m.global_value("OUT"), Some(&words(&[0, 14])));
    // Out of bounds: an error at the statement's line, not a guess.
    let err = m.run("main", vec![gid(2)]).expect_err("index 2 of 2");
    assert!(
        matches!(err, EvalError::At { line: 6, .. }),
        "{err:?} should point at line 6"
    );
    assert!(matches!(
        err.cause(),
        EvalError::OutOfBounds { index: 2, len: 2 }
    ));
}

#[test]
fn a_loop_that_never_ends_hits_the_step_limit() {
    let c = module("fn f(s: u32) -> u32 {\n let mut x = s;\n loop { x += 1u32; }\n x }");
    let err = Machine::new(&c.module, &c.keys[0].env)
        .with_step_limit(1000)
        .run("f", vec![Value::U32(0)])
        .expect_err("does not end");
    assert_eq!(err.cause(), &EvalError::StepLimit);
    assert!(err.to_string().contains("(at "), "{err}");
}
