//! Generated expressions and statement programs as plain host Rust over [`super::wgsl_rt`]:
//! the oracle's own reading of the DSL text that [`E::source`] and the program printer write.
//! Each DSL operator or method becomes the runtime function of the same meaning (`a + b` →
//! `add(a, b)`, `x.clamp(l, h)` → `clamp(x, l, h)`, `x as i32` → `to_i32(x)`); vectors are
//! arrays (`v.y` → `v[1]`, `v.zx()` → `[v[2], v[0]]`); control flow is Rust's own (`for` over
//! Rust ranges, `while`, `loop`, `break`, `continue`, shadowing `let`s). Nothing here goes
//! through `codegen`.

use super::ast::{E, Kind, Sc, T};
use super::program::{ARRAY_LEN, Place, Program, Shape, St};
use std::fmt::Write as _;

/// The host type of a DSL type (`[i32; 3]` for `IVec3`).
pub fn host_type(t: T) -> String {
    if t.n == 1 {
        t.s.name().into()
    } else {
        format!("[{}; {}]", t.s.name(), t.n)
    }
}

fn shape_type(s: Shape) -> String {
    match s {
        Shape::Value(t) => host_type(t),
        Shape::Array(s) => format!("[{}; {ARRAY_LEN}]", s.name()),
    }
}

fn lane(c: char) -> usize {
    "xyzw".find(c).unwrap_or(usize::MAX)
}

fn binary(op: &str) -> &'static str {
    match op {
        "+" => "add",
        "-" => "sub",
        "*" => "mul",
        "/" => "div",
        "%" => "rem",
        "&" => "and",
        "|" => "or",
        "^" => "xor",
        "<<" => "shl",
        ">>" => "shr",
        "&&" => "land",
        "||" => "lor",
        "==" => "eq",
        "!=" => "ne",
        "<" => "lt",
        "<=" => "le",
        ">" => "gt",
        ">=" => "ge",
        _ => "unknown_operator",
    }
}

/// A variable reference of a statement program (`p0s1`, `p0s3.y`, `p0s2[1]`) as host Rust.
fn var(text: &str) -> String {
    match text.split_once('.') {
        Some((v, c)) if c.len() == 1 => format!("{v}[{}]", lane(c.chars().next().unwrap_or('?'))),
        _ => text.into(),
    }
}

/// The host Rust of an expression.
pub fn expr(x: &E) -> String {
    let mut s = String::new();
    write(x, &mut s);
    s
}

fn write(x: &E, o: &mut String) {
    let call = |o: &mut String, f: &str, args: &[&E]| {
        let _ = write!(o, "{f}(");
        for (i, a) in args.iter().enumerate() {
            if i > 0 {
                o.push_str(", ");
            }
            write(a, o);
        }
        o.push(')');
    };
    match &x.kind {
        Kind::Input(i) => {
            let p = ["i", "u", "f", "b"][Sc::ALL.iter().position(|s| *s == x.ty.s).unwrap_or(0)];
            let _ = write!(o, "{p}{i}");
        }
        Kind::Var(v) => o.push_str(&var(v)),
        Kind::Lit(l) => {
            o.push_str(l);
            if x.ty.s == Sc::F32 && !l.ends_with("f32") {
                o.push_str("f32");
            }
        }
        Kind::Un("-", a) => call(o, "neg", &[a]),
        Kind::Un(_, a) => call(o, "not", &[a]),
        Kind::Bin(op, a, b) => {
            let name = binary(op);
            // Vector-scalar arithmetic: the scalar applies to every lane.
            if a.ty.n > 1 && b.ty.n == 1 && !matches!(*op, "<<" | ">>") {
                let _ = write!(o, "{name}(");
                write(a, o);
                o.push_str(", [");
                write(b, o);
                let _ = write!(o, "; {}])", a.ty.n);
            } else {
                call(o, name, &[a, b]);
            }
        }
        Kind::Cast(a) => call(o, &format!("to_{}", x.ty.s.name()), &[a]),
        Kind::AsVec(a) => call(o, &format!("to_{}", x.ty.s.name()), &[a]),
        Kind::Method(m, r, args) => {
            let all: Vec<&E> = std::iter::once(&**r).chain(args).collect();
            call(o, m, &all);
        }
        Kind::Select(c, t, f) => call(o, "select", &[c, t, f]),
        Kind::New(parts) => {
            // Each part once, then its lanes in order.
            o.push_str("({ ");
            let mut lanes = vec![];
            for (k, p) in parts.iter().enumerate() {
                let _ = write!(o, "let n{k}: {} = ", host_type(p.ty));
                write(p, o);
                o.push_str("; ");
                if p.ty.n == 1 {
                    lanes.push(format!("n{k}"));
                } else {
                    lanes.extend((0..p.ty.n).map(|c| format!("n{k}[{c}]")));
                }
            }
            let _ = write!(o, "[{}] }})", lanes.join(", "));
        }
        Kind::Splat(a) => {
            o.push('[');
            write(a, o);
            let _ = write!(o, "; {}]", x.ty.n);
        }
        Kind::Swizzle(a, s) => {
            let _ = write!(o, "({{ let v: {} = ", host_type(a.ty));
            write(a, o);
            let lanes: Vec<String> = s.chars().map(|c| format!("v[{}]", lane(c))).collect();
            if lanes.len() == 1 {
                let _ = write!(o, "; {} }})", lanes[0]);
            } else {
                let _ = write!(o, "; [{}] }})", lanes.join(", "));
            }
        }
        Kind::Index(v, i) => {
            // `v[(i % N)]`: the DSL text's own `%`, then the lane.
            o.push_str("index(");
            write(v, o);
            o.push_str(", rem(");
            write(i, o);
            let _ = write!(o, ", {}u32))", v.ty.n);
        }
    }
}

/// The input locals of a row, decoded from its 16 words `w` as the kernel's prelude does
/// (`IN[..] as i32`, `IN[..]`, `IN[..].from_bits()`, `IN[..] != 0u32`).
pub fn decode_inputs(per_type: usize) -> String {
    let mut s = String::new();
    for (t, p) in ["i", "u", "f", "b"].iter().enumerate() {
        for i in 0..per_type {
            let w = format!("w[{}]", t * per_type + i);
            let v = match *p {
                "i" => format!("to_i32({w})"),
                "u" => w,
                "f" => format!("f32::from_bits({w})"),
                _ => format!("{w} != 0"),
            };
            let _ = writeln!(s, "    let {p}{i} = {v};");
        }
    }
    s
}

/// The host Rust statements of a program, ending with the expression of its state words.
pub fn program(p: &Program) -> String {
    let mut o = String::new();
    for (name, shape, init) in &p.vars {
        let value = match shape {
            Shape::Value(_) => expr(&init[0]),
            Shape::Array(_) => {
                let items: Vec<String> = init.iter().map(expr).collect();
                format!("[{}]", items.join(", "))
            }
        };
        let _ = writeln!(o, "    let mut {name}: {} = {value};", shape_type(*shape));
    }
    block(&mut o, &p.body, 4);
    let parts: Vec<String> = p.vars.iter().map(|v| format!("words({})", v.0)).collect();
    let _ = writeln!(o, "    [{}].concat()", parts.join(", "));
    o
}

fn block(o: &mut String, b: &[St], indent: usize) {
    for s in b {
        stmt(o, s, indent);
    }
}

fn braced(o: &mut String, b: &[St], indent: usize) {
    o.push_str("{\n");
    block(o, b, indent + 4);
    let _ = write!(o, "{}}}", " ".repeat(indent));
}

fn compound(op: &str) -> &'static str {
    // `^=` on `bool` is `!=`, which `xor` is for `bool`.
    binary(op)
}

fn stmt(o: &mut String, s: &St, indent: usize) {
    let pad = " ".repeat(indent);
    o.push_str(&pad);
    match s {
        St::Assign(place, op, value) => {
            let target = match place {
                Place::Whole(v) => v.clone(),
                Place::Component(v, c) => format!("{v}[{}]", lane(*c)),
                Place::Indexed(v, n, i) => {
                    let _ = write!(o, "let k = rem({}, {n}u32) as usize; ", expr(i));
                    format!("{v}[k]")
                }
            };
            let v = expr(value);
            if op.is_empty() {
                let _ = writeln!(o, "{target} = {v};");
            } else {
                let _ = writeln!(o, "{target} = {}({target}, {v});", compound(op));
            }
        }
        St::Let(name, mutable, shape, value) => {
            let m = if *mutable { "mut " } else { "" };
            let t = shape_type(*shape);
            let _ = writeln!(o, "let {m}{name}: {t} = {};", expr(value));
        }
        St::If(c, then, els) => {
            let _ = write!(o, "if {} ", expr(c));
            braced(o, then, indent);
            if let Some(e) = els {
                o.push_str(" else ");
                braced(o, e, indent);
            }
            o.push('\n');
        }
        St::While(c, bound, cond, body) => {
            let _ = writeln!(o, "let mut {c}: u32 = 0;");
            let _ = write!(o, "{pad}while {c} < {bound} && {} ", expr(cond));
            let mut b = vec![St::Assign(Place::Whole(c.clone()), "+", one())];
            b.extend(body.iter().cloned());
            braced(o, &b, indent);
            o.push('\n');
        }
        St::Loop(c, bound, body) => {
            let _ = writeln!(o, "let mut {c}: u32 = 0;");
            let _ = writeln!(o, "{pad}loop {{");
            let inner = " ".repeat(indent + 4);
            let _ = writeln!(o, "{inner}{c} += 1;");
            let _ = writeln!(o, "{inner}if {c} > {bound} {{ break; }}");
            block(o, body, indent + 4);
            let _ = writeln!(o, "{pad}}}");
        }
        St::For(v, _, start, end, inclusive, body) => {
            let dots = if *inclusive { "..=" } else { ".." };
            let (a, b) = (expr(start), expr(end));
            let _ = write!(o, "for {v} in ({a}){dots}({b}) ");
            braced(o, body, indent);
            o.push('\n');
        }
        St::BreakIf(c) => {
            let _ = writeln!(o, "if {} {{ break; }}", expr(c));
        }
        St::ContinueIf(c) => {
            let _ = writeln!(o, "if {} {{ continue; }}", expr(c));
        }
        St::Block(b) => {
            braced(o, b, indent);
            o.push('\n');
        }
    }
}

fn one() -> E {
    E {
        ty: T::scalar(Sc::U32),
        kind: Kind::Lit("1u32".into()),
    }
}
