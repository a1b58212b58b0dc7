//! Random statement programs: state variables (integer and `bool` scalars, integer vectors,
//! `[T; 4]` arrays) changed by nested `if`/`else`, bounded `while`, `loop` and `for` loops
//! (exclusive, inclusive, ending at the type's maximum, with an end the body changes), guarded
//! `break` and `continue`, shadowing `let`s, and assignment and compound assignment to whole
//! variables, vector components (by name and by runtime index) and array elements. Every loop
//! ends by construction. Expressions come from the expression generator, with some input
//! leaves rebound to the variables in scope.
//!
//! Programs compute on integers and `bool`s only (no float reads either): a float comparison
//! within the driver's regrouping error could send the GPU down the other branch (see the
//! guide's Semantics section), and whole programs have no error bound. Floats are the
//! expression test's job, row by row with [`super::bound`].

use super::ast::{E, Kind, Sc, T};
use super::generate::{GenConfig, Rng, has_constant_lane, input, rgen};
use std::fmt::Write as _;

/// The shape of a state variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// A scalar or vector of type `T`.
    Value(T),
    /// `[s; 4]`.
    Array(Sc),
}

impl Shape {
    /// 32-bit output words.
    pub fn words(self) -> usize {
        match self {
            Shape::Value(t) => t.n as usize,
            Shape::Array(_) => ARRAY_LEN,
        }
    }

    /// The scalar type.
    pub fn scalar(self) -> Sc {
        match self {
            Shape::Value(t) => t.s,
            Shape::Array(s) => s,
        }
    }

    fn name(self) -> String {
        match self {
            Shape::Value(t) => t.name(),
            Shape::Array(s) => format!("[{}; {ARRAY_LEN}]", s.name()),
        }
    }
}

/// Elements of array state.
pub const ARRAY_LEN: usize = 4;

/// An assignment target.
#[derive(Debug, Clone, PartialEq)]
pub enum Place {
    /// The whole variable.
    Whole(String),
    /// `v.y`
    Component(String, char),
    /// `v[(i % n)]` / `a[(i % 4)]` with `i: u32`.
    Indexed(String, usize, E),
}

/// A statement.
#[derive(Debug, Clone, PartialEq)]
pub enum St {
    /// `place op= value` (`op` empty for plain assignment).
    Assign(Place, &'static str, E),
    /// `let [mut] name: T = value;` shadowing a state variable for the rest of its block.
    Let(String, bool, Shape, E),
    /// `if c { .. } [else { .. }]`
    If(E, Vec<St>, Option<Vec<St>>),
    /// `let mut c = 0u32; while c < bound && cond { c += 1u32; body }`
    While(String, u32, E, Vec<St>),
    /// `let mut c = 0u32; loop { c += 1u32; if c > bound { break; } body }`
    Loop(String, u32, Vec<St>),
    /// `for var in start..end` or `..=end`, over `ty`.
    For(String, Sc, E, E, bool, Vec<St>),
    /// `if c { break; }`
    BreakIf(E),
    /// `if c { continue; }`
    ContinueIf(E),
    /// `{ .. }`
    Block(Vec<St>),
}

/// One program: its state variables and its body.
#[derive(Debug, Clone, PartialEq)]
pub struct Program {
    /// State variables: name, shape, initial value (array elements for arrays).
    pub vars: Vec<(String, Shape, Vec<E>)>,
    /// Statements.
    pub body: Vec<St>,
}

/// A name in scope.
#[derive(Debug, Clone)]
struct Binding {
    name: String,
    shape: Shape,
    mutable: bool,
}

struct Gen<'r> {
    rng: &'r mut Rng,
    cfg: GenConfig,
    prefix: String,
    scope: Vec<Binding>,
    names: usize,
    budget: usize,
}

/// Generates program `id` (its names start with `p{id}`).
pub fn program(rng: &mut Rng, id: usize) -> Program {
    let cfg = GenConfig {
        depth: 2,
        raw_shifts: false,
        floats: false,
    };
    let mut g = Gen {
        rng,
        cfg,
        prefix: format!("p{id}"),
        scope: vec![],
        names: 0,
        budget: 14,
    };
    let mut vars = vec![];
    for _ in 0..2 + g.rng.below(3) {
        let shape = match g.rng.below(6) {
            0 => Shape::Value(T::scalar(Sc::Bool)),
            1 | 2 => Shape::Value(T::scalar(*g.rng.pick(&[Sc::I32, Sc::U32]))),
            3 | 4 => Shape::Value(T {
                n: 2 + g.rng.below(3) as u8,
                s: *g.rng.pick(&[Sc::I32, Sc::U32]),
            }),
            _ => Shape::Array(*g.rng.pick(&[Sc::I32, Sc::U32])),
        };
        let init = match shape {
            Shape::Value(t) => vec![g.expr(t)],
            Shape::Array(s) => (0..ARRAY_LEN).map(|_| g.expr(T::scalar(s))).collect(),
        };
        let name = g.fresh("s");
        g.scope.push(Binding {
            name: name.clone(),
            shape,
            mutable: true,
        });
        vars.push((name, shape, init));
    }
    let body = g.block(3, false);
    Program { vars, body }
}

impl Gen<'_> {
    fn fresh(&mut self, kind: &str) -> String {
        self.names += 1;
        format!("{}{kind}{}", self.prefix, self.names)
    }

    /// The bindings in scope, the innermost of each name (shadowing hides the others).
    fn visible(&self) -> Vec<Binding> {
        let mut seen = std::collections::HashSet::new();
        let mut out: Vec<Binding> = self
            .scope
            .iter()
            .rev()
            .filter(|b| seen.insert(b.name.clone()))
            .cloned()
            .collect();
        out.reverse();
        out
    }

    /// An expression of type `ty` over the inputs and the variables in scope.
    fn expr(&mut self, ty: T) -> E {
        let mut x = rgen(self.rng, ty, self.cfg.depth, self.cfg);
        self.bind(&mut x);
        x
    }

    fn cond(&mut self) -> E {
        self.expr(T::scalar(Sc::Bool))
    }

    /// Rebinds some input leaves to variables in scope of the same scalar type.
    fn bind(&mut self, x: &mut E) {
        if matches!(x.kind, Kind::Input(_)) && self.rng.chance(60) {
            let s = x.ty.s;
            let fits: Vec<Binding> = self
                .visible()
                .into_iter()
                .filter(|b| b.shape.scalar() == s)
                .collect();
            if !fits.is_empty() {
                let b = self.rng.pick(&fits).clone();
                let text = match b.shape {
                    Shape::Value(t) if t.n == 1 => b.name,
                    Shape::Value(t) => {
                        format!(
                            "{}.{}",
                            b.name,
                            &"xyzw"[self.rng.below(t.n as usize)..][..1]
                        )
                    }
                    Shape::Array(_) => format!("{}[{}]", b.name, self.rng.below(ARRAY_LEN)),
                };
                x.kind = Kind::Var(text);
            }
            return;
        }
        for c in x.children_mut() {
            self.bind(c);
        }
    }

    fn block(&mut self, depth: u32, in_loop: bool) -> Vec<St> {
        let saved = self.scope.len();
        let n = 1 + self.rng.below(3);
        let mut out = vec![];
        for _ in 0..n {
            if self.budget == 0 {
                break;
            }
            self.budget -= 1;
            out.push(self.stmt(depth, in_loop));
        }
        self.scope.truncate(saved);
        if out.is_empty() {
            out.push(self.assign());
        }
        out
    }

    fn stmt(&mut self, depth: u32, in_loop: bool) -> St {
        let k = self.rng.below(if depth == 0 { 4 } else { 20 });
        match k {
            0..=3 => self.assign(),
            4 if in_loop => St::BreakIf(self.cond()),
            5 if in_loop => St::ContinueIf(self.cond()),
            4..=6 => self.shadow(),
            7..=9 => {
                let c = self.cond();
                let then = self.block(depth - 1, in_loop);
                let els = self.rng.chance(50).then(|| self.block(depth - 1, in_loop));
                St::If(c, then, els)
            }
            10..=12 => {
                let counter = self.fresh("c");
                let c = self.cond();
                let bound = 1 + self.rng.below(4) as u32;
                self.readable(&counter, Sc::U32);
                let body = self.block(depth - 1, true);
                self.scope.pop();
                St::While(counter, bound, c, body)
            }
            13 | 14 => {
                let counter = self.fresh("c");
                let bound = 1 + self.rng.below(4) as u32;
                self.readable(&counter, Sc::U32);
                let body = self.block(depth - 1, true);
                self.scope.pop();
                St::Loop(counter, bound, body)
            }
            _ => self.for_loop(depth),
        }
    }

    /// A name the body may read but not assign.
    fn readable(&mut self, name: &str, s: Sc) {
        self.scope.push(Binding {
            name: name.into(),
            shape: Shape::Value(T::scalar(s)),
            mutable: false,
        });
    }

    fn for_loop(&mut self, depth: u32) -> St {
        let s = *self.rng.pick(&[Sc::I32, Sc::U32]);
        let t = T::scalar(s);
        let lit = |x: &str| E {
            ty: t,
            kind: Kind::Lit(format!("{x}{}", s.name())),
        };
        let small = |g: &mut Self, m: &str| E {
            ty: t,
            kind: Kind::Bin("%", Box::new(g.expr(t)), Box::new(lit(m))),
        };
        let (start, end, inclusive) = match self.rng.below(4) {
            // Ends at the type's maximum: `..=MAX` must stop.
            0 => {
                let max = E {
                    ty: t,
                    kind: Kind::Lit(format!("{}::MAX", s.name())),
                };
                // `MAX - k` with `k` in 0..3 (`abs` first for i32, whose `%` may be negative).
                let mut back = small(self, "3");
                if s == Sc::I32 {
                    back = E {
                        ty: t,
                        kind: Kind::Method("abs", Box::new(back), vec![]),
                    };
                }
                let start = E {
                    ty: t,
                    kind: Kind::Bin("-", Box::new(max.clone()), Box::new(back)),
                };
                (start, max, true)
            }
            k => (small(self, "4"), small(self, "5"), k == 1),
        };
        let var = self.fresh("j");
        self.readable(&var, s);
        let body = self.block(depth - 1, true);
        self.scope.pop();
        St::For(var, s, start, end, inclusive, body)
    }

    fn assign(&mut self) -> St {
        let targets: Vec<Binding> = self.visible().into_iter().filter(|b| b.mutable).collect();
        let b = self.rng.pick(&targets).clone();
        let s = b.shape.scalar();
        let (place, ty) = match b.shape {
            Shape::Value(t) if t.n == 1 || self.rng.chance(30) => (Place::Whole(b.name), t),
            Shape::Value(t) if self.rng.chance(50) => {
                let c = "xyzw".as_bytes()[self.rng.below(t.n as usize)] as char;
                (Place::Component(b.name, c), T::scalar(s))
            }
            shape => {
                let n = match shape {
                    Shape::Value(t) => t.n as usize,
                    Shape::Array(_) => ARRAY_LEN,
                };
                let i = self.expr(T::scalar(Sc::U32));
                (Place::Indexed(b.name, n, i), T::scalar(s))
            }
        };
        let ops: &[&'static str] = match s {
            Sc::Bool => &["", "&", "|", "^"],
            _ => &["", "+", "-", "*", "/", "%", "&", "|", "^", "<<", ">>"],
        };
        let op = *self.rng.pick(ops);
        let value = if op == "<<" || op == ">>" {
            let amount_ty = T {
                n: ty.n,
                s: Sc::U32,
            };
            let amount = self.expr(amount_ty);
            if amount.has_input() {
                amount
            } else {
                // A constant amount of 32 or more is a compile error (see the guide).
                let mask = E {
                    ty: T::scalar(Sc::U32),
                    kind: Kind::Lit("31u32".into()),
                };
                let mask = if ty.n == 1 {
                    mask
                } else {
                    E {
                        ty: amount_ty,
                        kind: Kind::Splat(Box::new(mask)),
                    }
                };
                E {
                    ty: amount_ty,
                    kind: Kind::Bin("&", Box::new(amount), Box::new(mask)),
                }
            }
        } else {
            let value = self.expr(ty);
            // A constant zero divisor, or a vector divisor with a constant zero lane, is a
            // compile error (naga; see the guide).
            if (op == "/" || op == "%") && has_constant_lane(&value) {
                input(self.rng, ty)
            } else {
                value
            }
        };
        St::Assign(place, op, value)
    }

    /// `{ let [mut] x = ..; .. }` shadowing a state variable of the same shape.
    fn shadow(&mut self) -> St {
        let values: Vec<Binding> = self
            .visible()
            .into_iter()
            .filter(|b| matches!(b.shape, Shape::Value(_)) && b.name.contains('s'))
            .collect();
        if values.is_empty() {
            return self.assign();
        }
        let b = self.rng.pick(&values).clone();
        let Shape::Value(t) = b.shape else {
            unreachable!("filtered to values")
        };
        let value = self.expr(t);
        let mutable = self.rng.chance(50);
        let saved = self.scope.len();
        self.scope.push(Binding {
            name: b.name.clone(),
            shape: b.shape,
            mutable,
        });
        let mut inner = vec![St::Let(b.name, mutable, b.shape, value)];
        inner.extend(self.block(0, false));
        self.scope.truncate(saved);
        St::Block(inner)
    }
}

impl Program {
    /// Output words.
    pub fn words(&self) -> usize {
        self.vars.iter().map(|v| v.1.words()).sum()
    }

    /// Statements, counted through nested blocks.
    pub fn size(&self) -> usize {
        fn count(b: &[St]) -> usize {
            b.iter()
                .map(|s| 1 + children(s).iter().map(|c| count(c)).sum::<usize>())
                .sum()
        }
        count(&self.body)
    }

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

fn children(s: &St) -> Vec<&Vec<St>> {
    match s {
        St::If(_, t, e) => std::iter::once(t).chain(e.as_ref()).collect(),
        St::While(.., b) | St::Loop(.., b) | St::For(.., b) | St::Block(b) => vec![b],
        _ => vec![],
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

/// Smaller programs: one statement removed, or a compound statement replaced by its body;
/// smallest first.
pub fn shrink_candidates(p: &Program) -> Vec<Program> {
    let n = p.size();
    let mut out = vec![];
    for at in 0..n {
        for how in 0..3 {
            let mut q = p.clone();
            let mut k = at;
            if edit(&mut q.body, &mut k, how) && q.size() < n {
                out.push(q);
            }
        }
    }
    out.sort_by_key(Program::size);
    out.dedup();
    out
}

/// Applies edit `how` to the statement at pre-order position `*k`: 0 removes it, 1 replaces
/// it by its (first) body, 2 by its `else` body.
fn edit(b: &mut Vec<St>, k: &mut usize, how: usize) -> bool {
    for i in 0..b.len() {
        if *k == 0 {
            let bodies: Vec<Vec<St>> = children(&b[i]).into_iter().cloned().collect();
            let replacement = match how {
                0 => vec![],
                1 if !bodies.is_empty() => bodies[0].clone(),
                2 if bodies.len() > 1 => bodies[1].clone(),
                _ => return false,
            };
            b.splice(i..=i, replacement);
            return true;
        }
        *k -= 1;
        let found = match &mut b[i] {
            St::If(_, t, e) => edit(t, k, how) || e.as_mut().is_some_and(|e| edit(e, k, how)),
            St::While(.., body) | St::Loop(.., body) | St::For(.., body) | St::Block(body) => {
                edit(body, k, how)
            }
            _ => false,
        };
        if found {
            return true;
        }
    }
    false
}
