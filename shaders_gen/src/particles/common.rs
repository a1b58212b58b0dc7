//! What every particle kernel shares: the emitter and particle records, and the seeded hash that
//! makes a particle's birth depend only on (seed, emitter, spawn index), so the GPU simulation
//! and the CPU one in `renderer::particles::reference` agree particle for particle.

/// Particle records, emitter parameters and the seeded random numbers of a birth.
///
/// `random(seed, emitter, index, channel)` is a PCG hash chain; `renderer::particles::random`
/// computes the same integers on the CPU.
#[shader_dsl::library]
pub mod particle_common {
    /// One emitter as kernels read it. Sizes are world half-widths; colours linear RGB with
    /// alpha, interpolated over a particle's life.
    pub struct GpuEmitter {
        /// Centre of the spawn sphere.
        pub position: Vec3,
        pub spawn_radius: f32,
        /// Mean initial velocity (its direction is the spread cone's axis).
        pub velocity: Vec3,
        /// Cosine of the cone's half angle.
        pub spread_cos: f32,
        pub gravity: Vec3,
        /// Velocity lost per second, as a fraction.
        pub drag: f32,
        /// Lifetime range in seconds.
        pub lifetime: Vec2,
        /// Initial speed varies by ± this fraction.
        pub speed_jitter: f32,
        /// Layer of the particle texture array.
        pub texture: u32,
        /// Half-width at birth and at death.
        pub size: Vec2,
        pub pad0: u32,
        pub pad1: u32,
        pub color_start: Vec4,
        pub color_end: Vec4,
    }

    /// One particle slot. `alive` is 0 for a free slot (on the dead list).
    pub struct GpuParticle {
        pub position: Vec3,
        pub age: f32,
        pub velocity: Vec3,
        pub lifetime: f32,
        /// The emitter and the particle's spawn index within it: its identity.
        pub emitter: u32,
        pub index: u32,
        pub alive: u32,
        pub pad: u32,
    }

    /// PCG's output permutation of one LCG step: a well-mixed 32-bit hash.
    pub fn pcg(v: u32) -> u32 {
        let state = v * 747796405u32 + 2891336453u32;
        let word = ((state >> ((state >> 28u32) + 4u32)) ^ state) * 277803737u32;
        (word >> 22u32) ^ word
    }

    /// A number in `[0, 1)` for random `channel` of the birth of particle `index` of `emitter`.
    pub fn random(seed: u32, emitter: u32, index: u32, channel: u32) -> f32 {
        let h = pcg(seed ^ pcg(emitter ^ pcg(index ^ pcg(channel))));
        (h >> 8u32) as f32 * (1.0 / 16777216.0)
    }

    /// How far through its life a particle is, 0 to 1.
    pub fn life(p: GpuParticle) -> f32 {
        (p.age / p.lifetime).saturate()
    }
}
