//! Casts between the scalar types and the float functions of the DSL, as plain Rust (see
//! [`super::wgsl_rt`] for the rules and where they come from).

use super::wgsl_rt::{Lanes, Scalar, dot, map, mark, note, sub, zip};

/// `as` conversions between the scalar types.
pub trait Cast: Scalar {
    /// `x as i32`
    fn to_i32(self) -> i32;
    /// `x as u32`
    fn to_u32(self) -> u32;
    /// `x as f32`
    fn to_f32(self) -> f32;
}

/// The largest `f32` that is also an `i32`: `2^31 - 128`.
const I32_MAX_F: f32 = 2_147_483_520.0;
/// The largest `f32` that is also a `u32`: `2^32 - 256`.
const U32_MAX_F: f32 = 4_294_967_040.0;

impl Cast for i32 {
    fn to_i32(self) -> i32 {
        self
    }
    fn to_u32(self) -> u32 {
        self.word()
    }
    fn to_f32(self) -> f32 {
        self as f32
    }
}

impl Cast for u32 {
    fn to_i32(self) -> i32 {
        i32::from_ne_bytes(self.to_ne_bytes())
    }
    fn to_u32(self) -> u32 {
        self
    }
    fn to_f32(self) -> f32 {
        self as f32
    }
}

impl Cast for f32 {
    fn to_i32(self) -> i32 {
        if self.is_nan() {
            mark();
            return 0;
        }
        // Within [-2^31, I32_MAX_F] after the clamp, so `as` only truncates.
        self.clamp(-2_147_483_648.0, I32_MAX_F).trunc() as i32
    }
    fn to_u32(self) -> u32 {
        if self.is_nan() {
            mark();
            return 0;
        }
        self.clamp(0.0, U32_MAX_F).trunc() as u32
    }
    fn to_f32(self) -> f32 {
        self
    }
}

impl Cast for bool {
    fn to_i32(self) -> i32 {
        i32::from(self)
    }
    fn to_u32(self) -> u32 {
        u32::from(self)
    }
    fn to_f32(self) -> f32 {
        if self { 1.0 } else { 0.0 }
    }
}

/// `x as i32`, `v.as_ivecN()`
pub fn to_i32<X: Lanes>(x: X) -> X::With<i32>
where
    X::S: Cast,
{
    map(x, Cast::to_i32)
}

/// `x as u32`, `v.as_uvecN()`
pub fn to_u32<X: Lanes>(x: X) -> X::With<u32>
where
    X::S: Cast,
{
    map(x, Cast::to_u32)
}

/// `x as f32`, `v.as_vecN()`
pub fn to_f32<X: Lanes>(x: X) -> X::With<f32>
where
    X::S: Cast,
{
    map(x, |x| note(x.to_f32()))
}

macro_rules! float1 {
    ($($name:ident = |$x:ident| $body:expr),* $(,)?) => {$(
        #[doc = concat!("`x.", stringify!($name), "()`, lane-wise.")]
        pub fn $name<X: Lanes<S = f32>>(x: X) -> X {
            map(x, |$x: f32| note($body)).lanes().pipe(Lanes::from_lanes)
        }
    )*};
}

trait Pipe: Sized {
    fn pipe<R>(self, f: impl FnOnce(Self) -> R) -> R {
        f(self)
    }
}

impl<T> Pipe for T {}

float1!(
    floor = |x| x.floor(),
    ceil = |x| x.ceil(),
    trunc = |x| x.trunc(),
    round = |x| x.round_ties_even(),
    fract = |x| x - x.floor(),
    saturate = |x| x.clamp(0.0, 1.0),
    signum = |x| if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    },
    sqrt = |x| x.sqrt(),
    inverse_sqrt = |x| 1.0 / x.sqrt(),
    sin = |x| x.sin(),
    cos = |x| x.cos(),
    exp = |x| x.exp(),
    exp2 = |x| x.exp2(),
    ln = |x| x.ln(),
    log2 = |x| x.log2(),
    to_radians = |x| x * (std::f32::consts::PI / 180.0),
);

/// `x.step(edge)`: 1 where `edge <= x`, else 0 (WGSL `step(edge, x)`).
pub fn step<X: Lanes<S = f32>>(x: X, edge: X) -> X {
    Lanes::from_lanes(zip(x, edge, |x, e| if e <= x { 1.0 } else { 0.0 }).lanes())
}

/// `x.mul_add(a, b)`: `x * a + b` (WGSL `fma`; rounding the product or not).
pub fn mul_add<X: Lanes<S = f32>>(x: X, a: X, b: X) -> X {
    let (x, a, b) = (x.lanes(), a.lanes(), b.lanes());
    Lanes::from_lanes(
        (0..x.len())
            .map(|i| note(x[i].mul_add(a[i], b[i])))
            .collect(),
    )
}

/// `v.length()`: `sqrt(v.dot(v))`.
pub fn length<X: Lanes<S = f32>>(v: X) -> f32 {
    note(dot(v, v).sqrt())
}

/// `v.normalize()`: `v / v.length()`.
pub fn normalize<X: Lanes<S = f32>>(v: X) -> X {
    let l = length(v);
    map(v, |x| note(x / l)).lanes().pipe(Lanes::from_lanes)
}

/// `v.distance(w)`: `(v - w).length()`.
pub fn distance<X: Lanes<S = f32>>(v: X, w: X) -> f32 {
    length(sub(v, w))
}
