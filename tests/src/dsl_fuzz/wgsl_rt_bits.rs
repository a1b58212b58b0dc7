//! Bit operations of the DSL's integers and `bool`s as plain Rust: `!`, `& | ^` (`^` on
//! `bool` is `!=`), `&&`, `||`, shifts by the low 5 bits of the amount (`>>` arithmetic on
//! `i32`), and bit counting of the operand's type (see [`super::wgsl_rt`]).

use super::wgsl_rt::{Lanes, Scalar, map, zip};

/// Bit operations of integers and `bool`.
pub trait Bits: Scalar {
    /// `!x`
    fn not(self) -> Self;
    /// `a & b`
    fn and(self, b: Self) -> Self;
    /// `a | b`
    fn or(self, b: Self) -> Self;
    /// `a ^ b` (`!=` on `bool`)
    fn xor(self, b: Self) -> Self;
}

macro_rules! int_bits {
    ($($t:ty),*) => {$(
        impl Bits for $t {
            fn not(self) -> $t {
                !self
            }
            fn and(self, b: $t) -> $t {
                self & b
            }
            fn or(self, b: $t) -> $t {
                self | b
            }
            fn xor(self, b: $t) -> $t {
                self ^ b
            }
        }
    )*};
}

int_bits!(i32, u32);

impl Bits for bool {
    fn not(self) -> bool {
        !self
    }
    fn and(self, b: bool) -> bool {
        self && b
    }
    fn or(self, b: bool) -> bool {
        self || b
    }
    fn xor(self, b: bool) -> bool {
        self != b
    }
}

/// `!x`
pub fn not<X: Lanes>(x: X) -> X
where
    X::S: Bits,
{
    Lanes::from_lanes(map(x, Bits::not).lanes())
}

macro_rules! bitwise2 {
    ($($name:ident),*) => {$(
        #[doc = concat!("`", stringify!($name), "`, lane-wise.")]
        pub fn $name<X: Lanes>(a: X, b: X) -> X
        where
            X::S: Bits,
        {
            Lanes::from_lanes(zip(a, b, Bits::$name).lanes())
        }
    )*};
}

bitwise2!(and, or, xor);

/// `a && b`
pub fn land(a: bool, b: bool) -> bool {
    a && b
}

/// `a || b`
pub fn lor(a: bool, b: bool) -> bool {
    a || b
}

/// A shift amount: its low 5 bits count.
pub trait Amount: Scalar {
    /// The amount, `0..32`.
    fn low5(self) -> u32;
}

impl Amount for u32 {
    fn low5(self) -> u32 {
        self & 31
    }
}

impl Amount for i32 {
    fn low5(self) -> u32 {
        self.word() & 31
    }
}

/// Integer shifts.
pub trait Shift: Scalar {
    /// `x << n`, `n < 32`.
    fn shl(self, n: u32) -> Self;
    /// `x >> n`, `n < 32` (arithmetic for `i32`).
    fn shr(self, n: u32) -> Self;
}

impl Shift for i32 {
    fn shl(self, n: u32) -> i32 {
        self << n
    }
    fn shr(self, n: u32) -> i32 {
        self >> n
    }
}

impl Shift for u32 {
    fn shl(self, n: u32) -> u32 {
        self << n
    }
    fn shr(self, n: u32) -> u32 {
        self >> n
    }
}

/// `x << n`
pub fn shl<X: Lanes, Y: Lanes>(x: X, n: Y) -> X
where
    X::S: Shift,
    Y::S: Amount,
{
    Lanes::from_lanes(zip(x, n, |x, n| x.shl(n.low5())).lanes())
}

/// `x >> n`
pub fn shr<X: Lanes, Y: Lanes>(x: X, n: Y) -> X
where
    X::S: Shift,
    Y::S: Amount,
{
    Lanes::from_lanes(zip(x, n, |x, n| x.shr(n.low5())).lanes())
}

/// Bit counting of integers (the result has the operand's type).
pub trait Count: Scalar {
    /// `count_ones`, `leading_zeros`, `trailing_zeros` as a count, `reverse_bits`.
    fn count(self, what: u8) -> Self;
}

impl Count for u32 {
    fn count(self, what: u8) -> u32 {
        match what {
            0 => self.count_ones(),
            1 => self.leading_zeros(),
            2 => self.trailing_zeros(),
            _ => self.reverse_bits(),
        }
    }
}

impl Count for i32 {
    fn count(self, what: u8) -> i32 {
        let bits = self.word().count(what);
        i32::from_ne_bytes(bits.to_ne_bytes())
    }
}

macro_rules! counts {
    ($($name:ident = $what:literal),*) => {$(
        #[doc = concat!("`x.", stringify!($name), "()`, of the operand's type.")]
        pub fn $name<X: Lanes>(x: X) -> X
        where
            X::S: Count,
        {
            Lanes::from_lanes(map(x, |x| x.count($what)).lanes())
        }
    )*};
}

counts!(
    count_ones = 0,
    leading_zeros = 1,
    trailing_zeros = 2,
    reverse_bits = 3
);
