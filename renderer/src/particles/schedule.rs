//! The fixed-step schedule both simulations follow: how many particles each emitter bears in
//! step `n`, and the spawn indices they get.

use shaders_gen::particles::particle_sim::SpawnBatch;

use super::Emitter;

/// The simulation's step, seconds (60 steps a second).
pub const FIXED_STEP: f32 = 1.0 / 60.0;

/// Births of an emitter before step `step`: `floor(step · rate · FIXED_STEP)`, in f64 so the
/// count is exact for any realistic run.
fn born_before(e: &Emitter, step: u64) -> u32 {
    (step as f64 * f64::from(e.rate) * f64::from(FIXED_STEP)).floor() as u32
}

/// This step's births, one batch per emitter that bears any: spawn indices
/// `first_index..first_index + count`, taken by spawn threads `base..base + count`.
pub fn spawn_batches(emitters: &[Emitter], step: u64) -> Vec<SpawnBatch> {
    let mut base = 0;
    let mut batches = Vec::new();
    for (i, e) in emitters.iter().enumerate() {
        let first = born_before(e, step);
        let count = born_before(e, step + 1) - first;
        if count > 0 {
            batches.push(SpawnBatch::new(i as u32, first, count, base));
            base += count;
        }
    }
    batches
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::particles::smoke;
    use glam::Vec3;

    #[test]
    fn a_second_of_steps_bears_the_rate_with_consecutive_indices() {
        let emitters = [smoke(Vec3::ZERO, 90.0), smoke(Vec3::ONE, 30.0)];
        let mut next = [0u32; 2];
        for step in 0..60 {
            let mut base = 0;
            for b in spawn_batches(&emitters, step) {
                assert!(b.count > 0);
                assert_eq!(b.first_index, next[b.emitter as usize], "consecutive");
                assert_eq!(b.base, base);
                next[b.emitter as usize] += b.count;
                base += b.count;
            }
        }
        assert_eq!(next, [90, 30]);
    }
}
