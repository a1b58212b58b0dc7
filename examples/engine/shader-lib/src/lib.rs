//! An engine's shader library crate: `surface` packs a shading normal with the renderer's
//! octahedral library (a library that uses a library of another crate) and owns a binding of
//! its own, the engine's tint, whose builder part modules of other crates bind by name.

/// The engine's surface helpers.
#[shader_dsl::library(uses(shaders_gen::shared::octahedral))]
pub mod surface {
    /// The engine's colour grading of lit surfaces.
    pub struct Tint {
        pub color: Vec3,
        pub strength: f32,
    }

    #[uniform(group = 1, binding = 0)]
    static TINT: Tint;

    /// `n` through the octahedral encoding and back: what a G-buffer would store.
    pub fn stored_normal(n: Vec3) -> Vec3 {
        octahedral_decode(octahedral_encode(n))
    }

    /// `c` blended towards the engine's tint.
    pub fn tinted(c: Vec3) -> Vec3 {
        c + (TINT.color - c) * TINT.strength
    }
}
