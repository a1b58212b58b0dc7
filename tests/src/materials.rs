//! Two materials written in the shader DSL, as an engine would write them
//! (`#[shader_dsl::material]`), for the material-program tests: a checkerboard with parameters
//! and a program without any.

/// A world-space checkerboard on the XZ plane: cells of `cell` metres alternate between
/// `first` and `second`, each the surface's base colour and, times `glow`, its emission. The
/// rest is glTF's material record (roughness and metalness factors, occlusion none).
#[shader_dsl::material(frame = shaders_gen::forward::material_frame, params = Checker)]
pub mod checker {
    /// The checkerboard's parameters.
    pub struct Checker {
        pub first: Vec4,
        pub second: Vec4,
        /// Cell side, metres.
        pub cell: f32,
        /// Emission per unit of base colour.
        pub glow: f32,
        pub pad: Vec2,
    }

    fn surface(point: MaterialPoint, params: Checker) -> Surface {
        let m = MATERIALS[point.material];
        let cell = (point.world.xz() / params.cell).floor();
        let odd = (cell.x + cell.y) - 2.0 * ((cell.x + cell.y) * 0.5).floor();
        let colour = select(odd > 0.5, params.second, params.first);
        Surface {
            base_color: colour,
            normal: point.normal,
            metallic: m.metallic,
            roughness: m.roughness,
            occlusion: 1.0,
            emissive: colour.xyz() * params.glow,
        }
    }
}

/// The geometric normal as base colour (`n × 0.5 + 0.5`), dielectric and rough: a program
/// without parameters.
#[shader_dsl::material(frame = shaders_gen::forward::material_frame)]
pub mod normal_colour {
    fn surface(point: MaterialPoint) -> Surface {
        Surface {
            base_color: (point.normal * 0.5 + 0.5).extend(1.0),
            normal: point.normal,
            metallic: 0.0,
            roughness: 0.8,
            occlusion: 1.0,
            emissive: Vec3::ZERO,
        }
    }
}
