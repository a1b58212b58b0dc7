//! Emitters and particle systems: what an engine describes, checked before it reaches the GPU.

use glam::{Vec3, Vec4};
use shaders_gen::particles::particle_sim::GpuEmitter;

/// The look of a particle: a layer of the built-in particle texture array.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParticleTexture {
    /// A soft round puff.
    Smoke = 0,
    /// A bright streak with a hot core.
    Spark = 1,
    /// A small hard-edged mote.
    Dust = 2,
}

/// A particle emitter. Particles are born in a sphere round `position` at `rate` per second,
/// fly off inside a cone round `velocity`, fall with `gravity`, slow with `drag`, and fade
/// from `color[0]` to `color[1]` and grow from `size[0]` to `size[1]` (world half-widths) over
/// a life drawn from `lifetime`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Emitter {
    /// Centre of the spawn sphere, world space (metres).
    pub position: Vec3,
    /// Radius of the sphere particles are born in, uniformly through its volume (metres, ≥ 0).
    pub spawn_radius: f32,
    /// Births per second.
    pub rate: f32,
    /// Shortest and longest life, seconds.
    pub lifetime: [f32; 2],
    /// Birth velocity, world space (m/s): its direction is the cone's axis, its length the
    /// speed (zero: particles are born at rest).
    pub velocity: Vec3,
    /// Half angle of the velocity cone, radians (0 to π).
    pub spread: f32,
    /// Initial speed varies by ± this fraction (0 to 1).
    pub speed_jitter: f32,
    /// Constant acceleration, world space (m/s²), e.g. `(0, -9.81, 0)`.
    pub gravity: Vec3,
    /// Fraction of velocity lost per second (0 to 60).
    pub drag: f32,
    /// Half-width at birth and at death, metres (> 0).
    pub size: [f32; 2],
    /// Linear RGB and alpha at birth and at death.
    pub color: [Vec4; 2],
    /// Radiance given off unlit, as a multiple of the colour (0: lit only; sparks glow).
    pub emissive: f32,
    /// Which built-in sprite it draws.
    pub texture: ParticleTexture,
}

/// Particle systems of a scene: emitters sharing one pool of `capacity` slots, simulated
/// deterministically from `seed`.
#[derive(Debug, Clone, PartialEq)]
pub struct ParticleSystem {
    /// The emitters; particles record the index of theirs.
    pub emitters: Vec<Emitter>,
    /// Particle slots. Births that find no free slot are counted and reported.
    pub capacity: u32,
    /// Seeds every birth's random draws: the same seed replays the same particles.
    pub seed: u32,
}

/// A particle system that cannot run, and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParticleError {
    /// An emitter has a value out of range or not finite ([`ParticleSystem::validate`]).
    #[error("particle emitter {index}: {reason}")]
    Emitter {
        /// The emitter's index in [`ParticleSystem::emitters`].
        index: usize,
        /// Which field is wrong and its allowed range.
        reason: String,
    },
    /// The capacity is over what the device holds.
    #[error(
        "{asked} particles are over this device's {max} (what one storage binding holds and one \
         dispatch reaches); lower the capacity"
    )]
    TooMany {
        /// The capacity asked for.
        asked: u32,
        /// The device's most.
        max: u32,
    },
    /// The capacity is 0.
    #[error("a particle system needs at least one slot (capacity is 0)")]
    NoCapacity,
    /// The lighting atlas side asked for is not a power of two within `min..=max`.
    #[error(
        "a particle lighting atlas of {asked}² texels cannot hold every particle at its smallest \
         region: use a power of two from {min} to this device's largest texture side, {max}"
    )]
    AtlasSize {
        /// The side asked for, texels.
        asked: u32,
        /// The smallest side that holds every particle at 2×2 texels.
        min: u32,
        /// The largest side: the device's largest texture side, at most 4096.
        max: u32,
    },
}

impl Emitter {
    /// The record kernels read.
    pub fn gpu(&self) -> GpuEmitter {
        GpuEmitter::new(
            self.position,
            self.spawn_radius,
            self.velocity,
            self.spread.cos(),
            self.gravity,
            self.drag,
            self.lifetime.into(),
            self.speed_jitter,
            self.texture as u32,
            self.size.into(),
            self.emissive,
            0,
            self.color[0],
            self.color[1],
        )
    }

    fn check(&self) -> Result<(), String> {
        let finite = self.position.is_finite()
            && self.velocity.is_finite()
            && self.gravity.is_finite()
            && self.color.iter().all(|c| c.is_finite());
        if !finite {
            return Err("position, velocity, gravity and colours must be finite".into());
        }
        let ranges = [
            ("spawn_radius", self.spawn_radius, 0.0, f32::MAX),
            ("rate", self.rate, 0.0, 1.0e7),
            ("spread", self.spread, 0.0, std::f32::consts::PI),
            ("speed_jitter", self.speed_jitter, 0.0, 1.0),
            ("drag", self.drag, 0.0, 60.0),
            ("emissive", self.emissive, 0.0, 1.0e4),
        ];
        for (name, value, lo, hi) in ranges {
            if !(lo..=hi).contains(&value) {
                return Err(format!("{name} {value} is outside {lo}..={hi}"));
            }
        }
        let [l0, l1] = self.lifetime;
        if !(l0 > 0.0 && l1 >= l0 && l1.is_finite()) {
            return Err(format!("lifetime [{l0}, {l1}] must be positive and rising"));
        }
        if !self.size.iter().all(|s| s.is_finite() && *s > 0.0) {
            return Err(format!("sizes {:?} must be positive", self.size));
        }
        Ok(())
    }
}

impl ParticleSystem {
    /// Checks every emitter and the capacity against `max_capacity` (what one storage binding
    /// holds on the device).
    pub fn validate(&self, max_capacity: u32) -> Result<(), ParticleError> {
        if self.capacity == 0 {
            return Err(ParticleError::NoCapacity);
        }
        if self.capacity > max_capacity {
            return Err(ParticleError::TooMany {
                asked: self.capacity,
                max: max_capacity,
            });
        }
        for (index, e) in self.emitters.iter().enumerate() {
            e.check()
                .map_err(|reason| ParticleError::Emitter { index, reason })?;
        }
        Ok(())
    }
}
