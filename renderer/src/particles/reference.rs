//! The CPU reference simulation: the same emitters and seed as the GPU, stepped on the host with
//! plain f32 maths. Tests compare the two particle by particle, matched by identity (emitter,
//! spawn index), since the GPU puts particles in whatever slot is free.
//!
//! The birth schedule is the reference's own, written from the emitter's documented semantics
//! (not from `schedule::spawn_batches`, which the GPU path uses): the clock advances by one
//! fixed step of `1/60` s (as an `f32`, the step particles age by) per step; an emitter of
//! `rate` births a second has borne `⌊rate · t⌋` particles by time `t` (in `f64`), so step `n`
//! bears spawn indices `⌊rate · n · step⌋ .. ⌊rate · (n + 1) · step⌋`, numbered from 0 per
//! emitter; within a step, emitters bear in list order and each in index order, and once the
//! pool is full every later birth of the step is refused and counted.

use glam::Vec3;

use super::random::random;
use super::{Emitter, ParticleSystem};

/// One step, seconds: 60 steps a second.
const STEP: f32 = 1.0 / 60.0;

/// One live particle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CpuParticle {
    pub emitter: u32,
    /// Spawn index within its emitter.
    pub index: u32,
    pub position: Vec3,
    pub velocity: Vec3,
    pub age: f32,
    pub lifetime: f32,
}

/// A particle system stepped on the CPU.
#[derive(Debug, Clone)]
pub struct CpuSimulation {
    system: ParticleSystem,
    steps: u64,
    /// Particles each emitter has borne (or had refused) so far: its next spawn index.
    borne: Vec<u32>,
    /// Live particles, in birth order.
    pub particles: Vec<CpuParticle>,
    /// Births refused because the pool was full.
    pub starved: u64,
}

/// A unit vector inside the cone of half-angle `acos(cos_max)` round unit `axis`.
fn in_cone(axis: Vec3, cos_max: f32, r0: f32, r1: f32) -> Vec3 {
    let helper = if axis.y.abs() < 0.99 {
        Vec3::Y
    } else {
        Vec3::X
    };
    let tangent = helper.cross(axis).normalize();
    let bitangent = axis.cross(tangent);
    let cos_t = 1.0 + (cos_max - 1.0) * r0;
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let phi = r1 * std::f32::consts::TAU;
    tangent * (sin_t * phi.cos()) + bitangent * (sin_t * phi.sin()) + axis * cos_t
}

/// Particle `index` of emitter number `emitter`, just born.
fn born(seed: u32, e: &Emitter, emitter: u32, index: u32) -> CpuParticle {
    let r = |channel| random(seed, emitter, index, channel);
    let lifetime = e.lifetime[0] + (e.lifetime[1] - e.lifetime[0]) * r(0);
    let cos_polar = r(1) * 2.0 - 1.0;
    let sin_polar = (1.0 - cos_polar * cos_polar).max(0.0).sqrt();
    let phi = r(2) * std::f32::consts::TAU;
    let radius = e.spawn_radius * r(3).powf(1.0 / 3.0);
    let offset = Vec3::new(sin_polar * phi.cos(), cos_polar, sin_polar * phi.sin()) * radius;
    let speed = e.velocity.length();
    let axis = if speed > 0.0 {
        e.velocity / speed
    } else {
        Vec3::Y
    };
    let jitter = 1.0 + e.speed_jitter * (r(6) * 2.0 - 1.0);
    CpuParticle {
        emitter,
        index,
        position: e.position + offset,
        velocity: in_cone(axis, e.spread.cos(), r(4), r(5)) * (speed * jitter),
        age: 0.0,
        lifetime,
    }
}

impl CpuSimulation {
    pub fn new(system: ParticleSystem) -> Self {
        Self {
            borne: vec![0; system.emitters.len()],
            system,
            steps: 0,
            particles: Vec::new(),
            starved: 0,
        }
    }

    /// One fixed step: age and move the live particles and drop the dead, then bear this
    /// step's births (they first move in the next step).
    pub fn step(&mut self) {
        let dt = STEP;
        let emitters = &self.system.emitters;
        for p in &mut self.particles {
            let e = &emitters[p.emitter as usize];
            p.velocity = (p.velocity + e.gravity * dt) * (1.0 - e.drag * dt).max(0.0);
            p.position += p.velocity * dt;
            p.age += dt;
        }
        self.particles.retain(|p| p.age < p.lifetime);
        // Births due by the end of this step: ⌊rate · t⌋ at t = (n + 1) steps for step n.
        let t = (self.steps + 1) as f64 * f64::from(STEP);
        for (i, e) in emitters.iter().enumerate() {
            let due = (f64::from(e.rate) * t).floor() as u32;
            for index in self.borne[i]..due {
                if self.particles.len() < self.system.capacity as usize {
                    let p = born(self.system.seed, e, i as u32, index);
                    self.particles.push(p);
                } else {
                    self.starved += 1;
                }
            }
            self.borne[i] = self.borne[i].max(due);
        }
        self.steps += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::particles::sparks;

    #[test]
    fn particles_live_their_lifetime_and_fall_under_gravity() {
        let mut e = sparks(Vec3::ZERO, 120.0);
        e.lifetime = [0.5, 0.5];
        let mut sim = CpuSimulation::new(ParticleSystem {
            emitters: vec![e],
            capacity: 10_000,
            seed: 3,
        });
        for _ in 0..120 {
            sim.step();
        }
        // 0.5 s lives at 120 a second: about 60 alive, none older than their life.
        assert!(
            (55..=65).contains(&sim.particles.len()),
            "{}",
            sim.particles.len()
        );
        assert!(sim.particles.iter().all(|p| p.age < p.lifetime));
        let falling = sim.particles.iter().filter(|p| p.velocity.y < 0.0).count();
        assert!(falling > 0, "gravity pulls sparks down");
        assert_eq!(sim.starved, 0);
    }

    /// The reference's births per step and emitter, as `(emitter, first index, count)`.
    fn reference_births(emitters: &[Emitter], steps: u64) -> Vec<Vec<(u32, u32, u32)>> {
        let mut sim = CpuSimulation::new(ParticleSystem {
            emitters: emitters.to_vec(),
            capacity: u32::MAX,
            seed: 1,
        });
        (0..steps)
            .map(|_| {
                let before = sim.borne.clone();
                sim.step();
                (0..emitters.len())
                    .filter(|&i| sim.borne[i] > before[i])
                    .map(|i| (i as u32, before[i], sim.borne[i] - before[i]))
                    .collect()
            })
            .collect()
    }

    #[test]
    fn the_reference_schedule_equals_the_gpu_schedule() {
        // Whole, fractional, slow (one birth every two seconds) and fast rates.
        let rates = [90.0, 30.0, 0.5, 33.3, 7.25, 1000.0];
        let emitters: Vec<Emitter> = rates.iter().map(|&r| sparks(Vec3::ZERO, r)).collect();
        let steps = 1200;
        let reference = reference_births(&emitters, steps);
        for (step, births) in reference.iter().enumerate() {
            let gpu: Vec<(u32, u32, u32)> =
                crate::particles::schedule::spawn_batches(&emitters, step as u64)
                    .iter()
                    .map(|b| (b.emitter, b.first_index, b.count))
                    .collect();
            assert_eq!(&gpu, births, "step {step}");
        }
        // Twenty seconds: every emitter has borne twenty seconds of its rate.
        let totals: Vec<u32> = (0..rates.len())
            .map(|i| {
                reference
                    .iter()
                    .flatten()
                    .filter(|b| b.0 == i as u32)
                    .map(|b| b.2)
                    .sum()
            })
            .collect();
        assert_eq!(totals, [1800, 600, 10, 666, 145, 20000]);
    }

    #[test]
    fn a_full_pool_refuses_births_and_counts_them() {
        let mut sim = CpuSimulation::new(ParticleSystem {
            emitters: vec![sparks(Vec3::ZERO, 600.0)],
            capacity: 20,
            seed: 3,
        });
        for _ in 0..10 {
            sim.step();
        }
        assert_eq!(sim.particles.len(), 20);
        assert_eq!(sim.starved, 100 - 20);
    }
}
