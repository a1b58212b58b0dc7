//! The DSL's documented runtime semantics as plain Rust, for the host-Rust oracle
//! ([`super::oracle`]). Written from `shader-dsl/GUIDE.md` ("Semantics", and the method table
//! of "Expressions", whose methods are WGSL's builtins), not from `codegen`: the oracle must
//! not share the DSL front end or the host interpreter. Scalars are Rust's `i32`, `u32`, `f32`
//! and `bool`; a vector is an array `[S; N]`. Every operation is a function, lane-wise on
//! vectors:
//!
//! - integer `+ - *` and negation wrap; `abs(i32::MIN) == i32::MIN`;
//! - `x / 0 == x`, `x % 0 == 0`, `i32::MIN / -1 == i32::MIN`, `i32::MIN % -1 == 0`; `%`
//!   truncates (the dividend's sign);
//! - shifts use the low 5 bits of the amount; `>>` is arithmetic on `i32`, logical on `u32`;
//! - float to integer casts truncate and saturate to the values both types hold
//!   (`[-2^31, 2147483520]` for `i32`, `[0, 4294967040]` for `u32`); integer casts keep bits;
//!   `bool` casts to 0 or 1;
//! - `^` on `bool` is `!=`; `x.clamp(lo, hi)` is `min(max(x, lo), hi)` (WGSL; for floats WGSL
//!   also allows the median when `lo > hi`, so such a row is indeterminate);
//! - `round` rounds half to even, `fract(x) = x - floor(x)`, `signum(0) = 0`,
//!   `x.step(edge)` is 1 where `edge <= x`, `x.mul_add(a, b) = x * a + b`;
//! - a float result that is NaN, infinite or subnormal marks the row indeterminate (WGSL leaves
//!   NaN results open; Vulkan may flush subnormals), as the differential test does.
//!
//! Bit operations are in [`super::wgsl_rt_bits`], casts and float functions in
//! [`super::wgsl_rt_float`]. The three files are compiled twice: as modules of this crate
//! (unit tests in `wgsl_rt_tests.rs`) and, as text, into every oracle program, where they
//! are sibling modules too.

#[cfg(test)]
#[path = "wgsl_rt_tests.rs"]
mod tests;

use std::cell::Cell;

thread_local! {
    static INDETERMINATE: Cell<bool> = const { Cell::new(false) };
}

/// Whether an indeterminate value was computed since the last call; clears the mark.
pub fn take_indeterminate() -> bool {
    INDETERMINATE.with(|c| c.replace(false))
}

/// Marks the row indeterminate.
pub fn mark() {
    INDETERMINATE.with(|c| c.set(true));
}

/// `x`, marking the row indeterminate when it is NaN, infinite or subnormal.
pub fn note(x: f32) -> f32 {
    if !x.is_finite() || x.is_subnormal() {
        mark();
    }
    x
}

/// A scalar type of the DSL.
pub trait Scalar: Copy + PartialEq + PartialOrd + std::fmt::Debug + Lanes<S = Self> {
    /// The value as the 32-bit word the kernel stores (`f32` bits, `i32` bits, `bool` 0/1).
    fn word(self) -> u32;
}

impl Scalar for i32 {
    fn word(self) -> u32 {
        u32::from_ne_bytes(self.to_ne_bytes())
    }
}

impl Scalar for u32 {
    fn word(self) -> u32 {
        self
    }
}

impl Scalar for f32 {
    fn word(self) -> u32 {
        self.to_bits()
    }
}

impl Scalar for bool {
    fn word(self) -> u32 {
        u32::from(self)
    }
}

/// A scalar (one lane) or a vector `[S; N]`.
pub trait Lanes: Copy {
    /// The scalar type.
    type S: Scalar;
    /// The same shape over another scalar type.
    type With<U: Scalar>: Lanes<S = U>;
    /// The lanes, in order.
    fn lanes(self) -> Vec<Self::S>;
    /// From lanes (as many as the shape has).
    fn from_lanes(v: Vec<Self::S>) -> Self;
}

macro_rules! scalar_lanes {
    ($($t:ty),*) => {$(
        impl Lanes for $t {
            type S = $t;
            type With<U: Scalar> = U;
            fn lanes(self) -> Vec<$t> {
                vec![self]
            }
            fn from_lanes(v: Vec<$t>) -> $t {
                v[0]
            }
        }
    )*};
}

scalar_lanes!(i32, u32, f32, bool);

impl<S: Scalar, const N: usize> Lanes for [S; N] {
    type S = S;
    type With<U: Scalar> = [U; N];
    fn lanes(self) -> Vec<S> {
        self.to_vec()
    }
    fn from_lanes(v: Vec<S>) -> [S; N] {
        std::array::from_fn(|i| v[i])
    }
}

/// `f` on every lane.
pub fn map<X: Lanes, U: Scalar>(a: X, f: impl Fn(X::S) -> U) -> X::With<U> {
    Lanes::from_lanes(a.lanes().into_iter().map(f).collect())
}

/// `f` on every pair of lanes.
pub fn zip<X: Lanes, Y: Lanes, U: Scalar>(a: X, b: Y, f: impl Fn(X::S, Y::S) -> U) -> X::With<U> {
    let (a, b) = (a.lanes(), b.lanes());
    assert_eq!(a.len(), b.len(), "operands of different widths");
    Lanes::from_lanes(a.into_iter().zip(b).map(|(x, y)| f(x, y)).collect())
}

/// The output words of a value, lane by lane.
pub fn words<X: Lanes>(x: X) -> Vec<u32> {
    x.lanes().into_iter().map(Scalar::word).collect()
}

/// Arithmetic of a numeric scalar type.
pub trait Num: Scalar {
    /// `a + b`
    fn add(self, b: Self) -> Self;
    /// `a - b`
    fn sub(self, b: Self) -> Self;
    /// `a * b`
    fn mul(self, b: Self) -> Self;
    /// `a / b`
    fn div(self, b: Self) -> Self;
    /// `a % b`
    fn rem(self, b: Self) -> Self;
    /// `a.abs()`
    fn abs(self) -> Self;
    /// `a.min(b)`
    fn min(self, b: Self) -> Self;
    /// `a.max(b)`
    fn max(self, b: Self) -> Self;
    /// `a.clamp(lo, hi)`
    fn clamp(self, lo: Self, hi: Self) -> Self {
        self.max(lo).min(hi)
    }
    /// The sum of products of `dot`.
    fn zero() -> Self;
}

impl Num for i32 {
    fn add(self, b: i32) -> i32 {
        self.wrapping_add(b)
    }
    fn sub(self, b: i32) -> i32 {
        self.wrapping_sub(b)
    }
    fn mul(self, b: i32) -> i32 {
        self.wrapping_mul(b)
    }
    fn div(self, b: i32) -> i32 {
        match b {
            0 => self,
            -1 if self == i32::MIN => i32::MIN,
            _ => self / b,
        }
    }
    fn rem(self, b: i32) -> i32 {
        match b {
            0 => 0,
            -1 => 0,
            _ => self % b,
        }
    }
    fn abs(self) -> i32 {
        self.wrapping_abs()
    }
    fn min(self, b: i32) -> i32 {
        if b < self { b } else { self }
    }
    fn max(self, b: i32) -> i32 {
        if b > self { b } else { self }
    }
    fn zero() -> i32 {
        0
    }
}

impl Num for u32 {
    fn add(self, b: u32) -> u32 {
        self.wrapping_add(b)
    }
    fn sub(self, b: u32) -> u32 {
        self.wrapping_sub(b)
    }
    fn mul(self, b: u32) -> u32 {
        self.wrapping_mul(b)
    }
    fn div(self, b: u32) -> u32 {
        self.checked_div(b).unwrap_or(self)
    }
    fn rem(self, b: u32) -> u32 {
        self.checked_rem(b).unwrap_or(0)
    }
    fn abs(self) -> u32 {
        self
    }
    fn min(self, b: u32) -> u32 {
        if b < self { b } else { self }
    }
    fn max(self, b: u32) -> u32 {
        if b > self { b } else { self }
    }
    fn zero() -> u32 {
        0
    }
}

impl Num for f32 {
    fn add(self, b: f32) -> f32 {
        note(self + b)
    }
    fn sub(self, b: f32) -> f32 {
        note(self - b)
    }
    fn mul(self, b: f32) -> f32 {
        note(self * b)
    }
    fn div(self, b: f32) -> f32 {
        note(self / b)
    }
    fn rem(self, b: f32) -> f32 {
        note(self - b * (self / b).trunc())
    }
    fn abs(self) -> f32 {
        note(self.abs())
    }
    fn min(self, b: f32) -> f32 {
        note(if b < self { b } else { self })
    }
    fn max(self, b: f32) -> f32 {
        note(if b > self { b } else { self })
    }
    fn clamp(self, lo: f32, hi: f32) -> f32 {
        let v = self.max(lo).min(hi);
        // WGSL: min(max(x, lo), hi) or the median of the three; they differ only if lo > hi.
        let median = self.max(lo.min(hi)).min(lo.max(hi));
        if v != median {
            mark();
        }
        v
    }
    fn zero() -> f32 {
        0.0
    }
}

macro_rules! lanewise2 {
    ($($name:ident),*) => {$(
        #[doc = concat!("`", stringify!($name), "`, lane-wise.")]
        pub fn $name<X: Lanes>(a: X, b: X) -> X
        where
            X::S: Num,
        {
            Lanes::from_lanes(zip(a, b, Num::$name).lanes())
        }
    )*};
}

lanewise2!(add, sub, mul, div, rem, min, max);

/// `x.abs()`
pub fn abs<X: Lanes>(x: X) -> X
where
    X::S: Num,
{
    Lanes::from_lanes(map(x, Num::abs).lanes())
}

/// `x.clamp(lo, hi)`
pub fn clamp<X: Lanes>(x: X, lo: X, hi: X) -> X
where
    X::S: Num,
{
    let (x, lo, hi) = (x.lanes(), lo.lanes(), hi.lanes());
    Lanes::from_lanes((0..x.len()).map(|i| x[i].clamp(lo[i], hi[i])).collect())
}

/// `v.dot(w)`: the sum of the lane products, in lane order.
pub fn dot<X: Lanes>(a: X, b: X) -> X::S
where
    X::S: Num,
{
    zip(a, b, Num::mul)
        .lanes()
        .into_iter()
        .fold(<X::S as Num>::zero(), Num::add)
}

/// Negation and bitwise or logical not.
pub trait Signed: Scalar {
    /// Unary `-` (wrapping for `i32`).
    fn neg(self) -> Self;
}

impl Signed for i32 {
    fn neg(self) -> i32 {
        self.wrapping_neg()
    }
}

impl Signed for f32 {
    fn neg(self) -> f32 {
        -self
    }
}

/// Unary `-`.
pub fn neg<X: Lanes>(x: X) -> X
where
    X::S: Signed,
{
    Lanes::from_lanes(map(x, Signed::neg).lanes())
}

macro_rules! compare {
    ($($name:ident $op:tt),*) => {$(
        #[doc = concat!("`a ", stringify!($op), " b` (false when a float operand is NaN).")]
        pub fn $name<S: Scalar>(a: S, b: S) -> bool {
            a $op b
        }
    )*};
}

compare!(eq ==, ne !=, lt <, le <=, gt >, ge >=);

/// `select(cond, if_true, if_false)`
pub fn select<X: Lanes>(cond: bool, if_true: X, if_false: X) -> X {
    if cond { if_true } else { if_false }
}

/// `v[i]` for an index already reduced below the width.
pub fn index<S: Scalar, const N: usize>(v: [S; N], i: u32) -> S {
    v[i as usize]
}
