//! The built-in emitters: smoke, sparks and dust, each a function of where it stands and how
//! many particles it bears a second, so the demo and `--particles N` need no files.

use glam::{Vec3, Vec4};

use super::{Emitter, ParticleSystem, ParticleTexture};
use crate::scene::Aabb;

/// A slow grey plume rising, widening and thinning over 3–5 s.
pub fn smoke(position: Vec3, rate: f32) -> Emitter {
    Emitter {
        position,
        spawn_radius: 0.15,
        rate,
        lifetime: [3.0, 5.0],
        velocity: Vec3::new(0.0, 0.6, 0.0),
        spread: 0.35,
        speed_jitter: 0.4,
        gravity: Vec3::new(0.05, 0.15, 0.0),
        drag: 0.3,
        size: [0.15, 0.7],
        color: [
            Vec4::new(0.55, 0.55, 0.55, 0.5),
            Vec4::new(0.7, 0.7, 0.72, 0.0),
        ],
        emissive: 0.0,
        texture: ParticleTexture::Smoke,
    }
}

/// A fountain of fast, small, hot sparks falling back under gravity in under a second.
pub fn sparks(position: Vec3, rate: f32) -> Emitter {
    Emitter {
        position,
        spawn_radius: 0.05,
        rate,
        lifetime: [0.5, 1.0],
        velocity: Vec3::new(0.0, 3.5, 0.0),
        spread: 0.6,
        speed_jitter: 0.5,
        gravity: Vec3::new(0.0, -9.8, 0.0),
        drag: 0.5,
        size: [0.03, 0.015],
        color: [
            Vec4::new(4.0, 2.0, 0.6, 1.0),
            Vec4::new(1.5, 0.3, 0.05, 0.0),
        ],
        emissive: 1.0,
        texture: ParticleTexture::Spark,
    }
}

/// Motes drifting through a wide volume for a long time.
pub fn dust(position: Vec3, rate: f32) -> Emitter {
    Emitter {
        position,
        spawn_radius: 3.0,
        rate,
        lifetime: [6.0, 10.0],
        velocity: Vec3::new(0.05, 0.02, 0.0),
        spread: std::f32::consts::PI,
        speed_jitter: 1.0,
        gravity: Vec3::ZERO,
        drag: 0.05,
        size: [0.02, 0.02],
        color: [
            Vec4::new(0.8, 0.75, 0.6, 0.6),
            Vec4::new(0.8, 0.75, 0.6, 0.0),
        ],
        emissive: 0.0,
        texture: ParticleTexture::Dust,
    }
}

/// Smoke, sparks and dust placed in `bounds` (on its floor, a third and two thirds across, and
/// in its middle), together bearing about `per_second` particles a second.
pub fn builtin_emitters(bounds: Aabb, per_second: f32) -> Vec<Emitter> {
    let (min, max) = (bounds.min, bounds.max);
    let at = |fx: f32, fy: f32, fz: f32| min + (max - min) * Vec3::new(fx, fy, fz);
    vec![
        smoke(at(0.35, 0.0, 0.45), per_second * 0.5),
        sparks(at(0.65, 0.0, 0.55), per_second * 0.3),
        dust(at(0.5, 0.2, 0.5), per_second * 0.2),
    ]
}

/// Fixed steps a frame's particles are simulated before they are first shown: 5 s, so that
/// every built-in emitter is under way.
pub const WARMUP_STEPS: u32 = 300;

/// The built-in emitters in `bounds` sized for about `count` live particles (90% of a pool of
/// `count` slots, at their rate-weighted mean lifetime), seeded.
pub fn builtin_system(bounds: Aabb, count: u32, seed: u32) -> ParticleSystem {
    let lifetime: f32 = builtin_emitters(bounds, 1.0)
        .iter()
        .map(|e| e.rate * (e.lifetime[0] + e.lifetime[1]) * 0.5)
        .sum();
    ParticleSystem {
        emitters: builtin_emitters(bounds, count as f32 * 0.9 / lifetime),
        capacity: count,
        seed,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::particles::ParticleError;

    #[test]
    fn bad_emitters_and_capacities_are_refused_with_the_reason() {
        let ok = ParticleSystem {
            emitters: vec![smoke(Vec3::ZERO, 100.0)],
            capacity: 1000,
            seed: 1,
        };
        assert_eq!(ok.validate(1 << 20), Ok(()));
        let mut bad = ok.clone();
        bad.emitters[0].lifetime = [2.0, 1.0];
        let err = bad.validate(1 << 20).unwrap_err().to_string();
        assert!(
            err.contains("emitter 0") && err.contains("lifetime"),
            "{err}"
        );
        bad.emitters[0] = smoke(Vec3::NAN, 100.0);
        assert!(bad.validate(1 << 20).is_err());
        assert_eq!(
            ok.validate(999),
            Err(ParticleError::TooMany {
                asked: 1000,
                max: 999
            })
        );
        let empty = ParticleSystem { capacity: 0, ..ok };
        assert_eq!(empty.validate(10), Err(ParticleError::NoCapacity));
    }
}
