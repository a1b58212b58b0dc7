//! Unit tests of the oracle runtime against the guide's examples.

use super::*;
use crate::dsl_fuzz::wgsl_rt_bits::*;
use crate::dsl_fuzz::wgsl_rt_float::*;

#[test]
fn integer_rules_of_the_guide() {
    assert_eq!(add(i32::MAX, 1), i32::MIN);
    assert_eq!(neg(i32::MIN), i32::MIN);
    assert_eq!(abs(i32::MIN), i32::MIN);
    assert_eq!(shl(1u32, 33u32), 2);
    assert_eq!(shr(-8i32, 1u32), -4);
    assert_eq!(shr(0x8000_0000u32, 31i32), 1);
    assert_eq!(div(7i32, 0), 7);
    assert_eq!(rem(7u32, 0), 0);
    assert_eq!(div(i32::MIN, -1), i32::MIN);
    assert_eq!(rem(i32::MIN, -1), 0);
    assert_eq!(rem(-7i32, 2), -1);
    assert_eq!(clamp(5i32, 3, 1), 1);
    assert!(!xor(true, true));
    assert_eq!(count_ones(-1i32), 32);
    assert_eq!(leading_zeros([0u32, 1]), [32, 31]);
}

#[test]
fn float_rules_of_the_guide() {
    assert_eq!(to_i32(1e10f32), 2_147_483_520);
    assert_eq!(to_u32(-1.0f32), 0);
    assert_eq!(to_i32(-2.7f32), -2);
    assert_eq!(round([0.5f32, 1.5, -2.5]), [0.0, 2.0, -2.0]);
    assert_eq!(fract(-0.25f32), 0.75);
    assert_eq!(signum(0.0f32), 0.0);
    assert_eq!(step(1.0f32, 2.0), 0.0);
    assert_eq!(step(2.0f32, 2.0), 1.0);
    assert!(!take_indeterminate());
    let _ = clamp(3.0f32, 2.0, 1.0);
    assert!(take_indeterminate());
    let _ = div(1.0f32, 0.0);
    assert!(take_indeterminate());
    assert!(!take_indeterminate());
}
