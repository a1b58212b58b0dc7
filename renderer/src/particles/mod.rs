//! GPU particles, the GPU-free half: emitters and the particle systems an engine hands the
//! renderer (`ParticleSystem`, validated with typed errors), the built-in smoke, sparks and dust
//! emitters, the fixed-step spawn schedule both simulations follow, the seeded hash of a birth,
//! and the CPU reference simulation (`reference`) that the GPU one is tested against.
//!
//! On the GPU, `crate::passes::particles` simulates (`shaders_gen::particles::particle_sim`)
//! and sorts (`particle_sort`) them.

mod builtin;
mod emitter;
#[cfg(any(test, feature = "internals"))]
#[doc(hidden)]
pub mod reference;

internal_modules!(random, schedule, sprites);

pub use builtin::{WARMUP_STEPS, builtin_emitters, builtin_system, dust, smoke, sparks};
pub use emitter::{Emitter, ParticleError, ParticleSystem, ParticleTexture};
pub use schedule::FIXED_STEP;
