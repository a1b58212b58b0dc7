//! Generation of random statement programs (see [`super::program`]): a scope of bindings,
//! a statement budget, and rebinding of expression inputs to the variables in scope.

use super::ast::{E, Kind, Sc, T};
use super::generate::{GenConfig, Rng, has_constant_lane, input, rgen};
use super::program::{ARRAY_LEN, Place, Program, Shape, St};

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
