//! The seeded hash of a particle's birth, the same integer operations as
//! `shaders_gen::particles::particle_common::{pcg, random}`: a birth depends only on
//! (seed, emitter, spawn index, channel).

/// PCG's output permutation of one LCG step.
pub fn pcg(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// A number in `[0, 1)` for random `channel` of the birth of particle `index` of `emitter`.
#[cfg(any(test, feature = "internals"))]
pub fn random(seed: u32, emitter: u32, index: u32, channel: u32) -> f32 {
    let h = pcg(seed ^ pcg(emitter ^ pcg(index ^ pcg(channel))));
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_in_range_and_spread() {
        let values: Vec<f32> = (0..4096).map(|i| random(7, 1, i, 0)).collect();
        assert!(values.iter().all(|v| (0.0..1.0).contains(v)));
        let mean = values.iter().sum::<f32>() / values.len() as f32;
        assert!((mean - 0.5).abs() < 0.02, "mean {mean}");
        assert_ne!(random(7, 1, 5, 0), random(8, 1, 5, 0), "the seed matters");
        assert_ne!(random(7, 1, 5, 0), random(7, 1, 5, 1), "channels differ");
    }
}
