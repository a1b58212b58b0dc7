//! The DSL text of a statement program: its state `let`s, its statements, and the stores of
//! its state to the kernel's output words.

use super::ast::{E, Kind, Sc, T};
use super::program::{ARRAY_LEN, Place, Program, Shape, St};
use std::fmt::Write as _;

impl Program {
    /// The program as DSL statements (inside the kernel's own block), storing its state to
    /// `OUT[o + slot..]`.
    pub fn source(&self, slot: usize, indent: usize) -> String {
        let mut o = String::new();
        let pad = " ".repeat(indent);
        for (name, shape, init) in &self.vars {
            let init: Vec<String> = init.iter().map(E::source).collect();
            let value = match shape {
                Shape::Value(_) => init[0].clone(),
                Shape::Array(_) => format!("[{}]", init.join(", ")),
            };
            let _ = writeln!(o, "{pad}let mut {name}: {} = {value};", shape.name());
        }
        write_block(&mut o, &self.body, indent);
        let mut k = slot;
        for (name, shape, _) in &self.vars {
            let comps: Vec<String> = match shape {
                Shape::Value(t) if t.n == 1 => vec![name.clone()],
                Shape::Value(t) => (0..t.n as usize)
                    .map(|c| format!("{name}.{}", &"xyzw"[c..c + 1]))
                    .collect(),
                Shape::Array(_) => (0..ARRAY_LEN).map(|c| format!("{name}[{c}]")).collect(),
            };
            for c in comps {
                let store = match shape.scalar() {
                    Sc::U32 => c,
                    _ => format!("{c} as u32"),
                };
                let _ = writeln!(o, "{pad}OUT[o + {k}u32] = {store};");
                k += 1;
            }
        }
        o
    }
}

fn write_block(o: &mut String, b: &[St], indent: usize) {
    for s in b {
        write_stmt(o, s, indent);
    }
}

fn braced(o: &mut String, b: &[St], indent: usize) {
    o.push_str("{\n");
    write_block(o, b, indent + 4);
    let _ = write!(o, "{}}}", " ".repeat(indent));
}

fn write_stmt(o: &mut String, s: &St, indent: usize) {
    let pad = " ".repeat(indent);
    o.push_str(&pad);
    match s {
        St::Assign(place, op, value) => {
            let target = match place {
                Place::Whole(v) => v.clone(),
                Place::Component(v, c) => format!("{v}.{c}"),
                Place::Indexed(v, n, i) => format!("{v}[({} % {n}u32)]", i.source()),
            };
            let _ = writeln!(o, "{target} {op}= {};", value.source());
        }
        St::Let(name, mutable, shape, value) => {
            let m = if *mutable { "mut " } else { "" };
            let _ = writeln!(o, "let {m}{name}: {} = {};", shape.name(), value.source());
        }
        St::If(c, then, els) => {
            let _ = write!(o, "if {} ", c.source());
            braced(o, then, indent);
            if let Some(e) = els {
                o.push_str(" else ");
                braced(o, e, indent);
            }
            o.push('\n');
        }
        St::While(c, bound, cond, body) => {
            let _ = writeln!(o, "let mut {c} = 0u32;");
            let _ = write!(o, "{pad}while {c} < {bound}u32 && {} ", cond.source());
            let mut b = vec![St::Assign(Place::Whole(c.clone()), "+", lit_u32(1))];
            b.extend(body.iter().cloned());
            braced(o, &b, indent);
            o.push('\n');
        }
        St::Loop(c, bound, body) => {
            let _ = writeln!(o, "let mut {c} = 0u32;");
            let _ = writeln!(o, "{pad}loop {{");
            let inner = " ".repeat(indent + 4);
            let _ = writeln!(o, "{inner}{c} += 1u32;");
            let _ = writeln!(o, "{inner}if {c} > {bound}u32 {{ break; }}");
            write_block(o, body, indent + 4);
            let _ = writeln!(o, "{pad}}}");
        }
        St::For(var, _, start, end, inclusive, body) => {
            let dots = if *inclusive { "..=" } else { ".." };
            let _ = write!(o, "for {var} in {}{dots}{} ", start.source(), end.source());
            braced(o, body, indent);
            o.push('\n');
        }
        St::BreakIf(c) => {
            let _ = writeln!(o, "if {} {{ break; }}", c.source());
        }
        St::ContinueIf(c) => {
            let _ = writeln!(o, "if {} {{ continue; }}", c.source());
        }
        St::Block(b) => {
            braced(o, b, indent);
            o.push('\n');
        }
    }
}

fn lit_u32(v: u32) -> E {
    E {
        ty: T::scalar(Sc::U32),
        kind: Kind::Lit(format!("{v}u32")),
    }
}
