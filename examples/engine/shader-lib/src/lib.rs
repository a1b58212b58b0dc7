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

/// Procedural patterns for the engine's materials, over the renderer's material surface types
/// (`MaterialPoint`, `Surface`; a library of another crate): no bindings of its own, so any
/// material program may use it.
#[shader_dsl::library(uses(shaders_gen::forward::material_surface))]
pub mod patterns {
    /// 1 inside a brick, 0 in the mortar: running-bond bricks of `size` (width, height) in the
    /// plane of a vertical face at `p` (its unit normal `n`), joints `mortar` wide.
    pub fn brick_mask(p: Vec3, n: Vec3, size: Vec2, mortar: f32) -> f32 {
        // Along the face: x on faces that look along ±Z, z on faces that look along ±X.
        let along = select(n.x.abs() > n.z.abs(), p.z, p.x);
        let row = (p.y / size.y).floor();
        let shifted = along / size.x + 0.5 * (row - 2.0 * (row * 0.5).floor());
        let u = shifted - shifted.floor();
        let v = p.y / size.y - row;
        let ju = mortar / size.x;
        let jv = mortar / size.y;
        let inside = u > ju && u < 1.0 - ju && v > jv && v < 1.0 - jv;
        select(inside, 1.0, 0.0)
    }

    /// A dielectric surface of `colour` and `roughness` at `point`'s geometric normal.
    pub fn pattern_surface(point: MaterialPoint, colour: Vec3, roughness: f32) -> Surface {
        Surface {
            base_color: colour.extend(1.0),
            normal: point.normal,
            metallic: 0.0,
            roughness,
            occlusion: 1.0,
            emissive: Vec3::ZERO,
        }
    }
}
