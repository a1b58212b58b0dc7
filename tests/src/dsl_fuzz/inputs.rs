//! The input rows of a batch: random rows of the 16 input words (`i0..i3`, `u0..u3`,
//! `f0..f3` as bits, `b0..b3` as 0/1), and a row as text for failure reports.

use super::ast::INPUTS_PER_TYPE;
use super::generate::Rng;
use std::fmt::Write as _;

/// Invocations per dispatch: each runs every expression on its own random inputs.
pub const ROWS: usize = 64;
/// 32-bit input words per invocation: `i0..i3`, `u0..u3`, `f0..f3` (bits), `b0..b3` (0/1).
pub const WORDS: usize = 4 * INPUTS_PER_TYPE;

/// Random input rows: special values often, full-range values sometimes; floats are finite
/// and coarse enough that exact operations stay away from subnormals.
pub fn inputs(rng: &mut Rng) -> Vec<u32> {
    let mut v = Vec::with_capacity(ROWS * WORDS);
    for _ in 0..ROWS {
        for _ in 0..INPUTS_PER_TYPE {
            let i: i32 = match rng.below(4) {
                0 => *rng.pick(&[0, 1, -1, 2, i32::MIN, i32::MAX, 31, 32, -32]),
                1 => rng.below(33) as i32 - 16,
                2 => rng.next_u64() as i32,
                _ => (rng.below(2001) as i32) - 1000,
            };
            v.push(i as u32);
        }
        for _ in 0..INPUTS_PER_TYPE {
            v.push(match rng.below(4) {
                0 => *rng.pick(&[0, 1, 2, u32::MAX, 31, 32, 33, 0x8000_0000]),
                1 => rng.below(40) as u32,
                2 => rng.next_u64() as u32,
                _ => rng.below(100_000) as u32,
            });
        }
        for _ in 0..INPUTS_PER_TYPE {
            let f: f32 = match rng.below(4) {
                0 => *rng.pick(&[0.0, -0.0, 1.0, -1.0, 0.5, 2.5, -2.5, 1e6, 3.0e9, -3.0e9]),
                1 => (rng.below(8193) as f32 - 4096.0) / 16.0,
                2 => (rng.below(41) as f32) - 20.0,
                _ => (rng.below(2_000_001) as f32 - 1_000_000.0) / 256.0,
            };
            v.push(f.to_bits());
        }
        for _ in 0..INPUTS_PER_TYPE {
            v.push(rng.below(2) as u32);
        }
    }
    v
}

/// The input row as text (`i0 = .., f2 = ..`).
pub fn describe_row(inputs: &[u32], row: usize) -> String {
    let w = &inputs[row * WORDS..(row + 1) * WORDS];
    let mut s = String::new();
    for (t, p) in ["i", "u", "f", "b"].iter().enumerate() {
        for i in 0..INPUTS_PER_TYPE {
            let bits = w[t * INPUTS_PER_TYPE + i];
            let v = match *p {
                "i" => format!("{}", bits as i32),
                "u" => format!("{bits}"),
                "f" => format!("{:?}", f32::from_bits(bits)),
                _ => format!("{}", bits != 0),
            };
            let _ = write!(s, "{p}{i} = {v}, ");
        }
    }
    s.truncate(s.len() - 2);
    s
}
