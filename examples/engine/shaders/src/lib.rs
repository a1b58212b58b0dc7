//! An engine's shader modules: a compute module that uses its own library crate's `surface`
//! library and the renderer's PBR library, over an axis of its own; and a material, `bricks`,
//! written with the renderer's material frame and its library crate's `patterns`, which the
//! renderer draws on every path.

/// Lights a list of points with one light: the renderer's `shade_light`, the engine's normal
/// packing and tint.
#[shader_dsl::shader(
    axes(packed: bool = [false, true] => "packed"),
    uses(engine_shader_lib::surface, shaders_gen::shared::pbr),
)]
pub mod engine_lit {
    pub struct Point {
        pub position: Vec3,
        pub roughness: f32,
        pub normal: Vec3,
        pub metallic: f32,
    }

    #[storage(group = 0, binding = 0)]
    static POINTS: [Point];
    #[storage(group = 0, binding = 1)]
    static LIGHT: [GpuLight];
    #[storage(group = 0, binding = 2, read_write)]
    static OUT: [Vec4];

    #[compute(workgroup_size(64, 1, 1))]
    pub fn main(#[builtin(global_invocation_id)] gid: UVec3) {
        let p = POINTS[gid.x];
        let mut n = p.normal;
        if packed {
            n = stored_normal(n);
        }
        let v = Vec3::new(0.0, 0.0, 1.0);
        let c = shade_light(
            LIGHT[0],
            p.position,
            n,
            v,
            Vec3::new(0.8, 0.8, 0.8),
            p.metallic,
            p.roughness,
        );
        OUT[gid.x] = tinted(c).extend(1.0);
    }
}

/// Running-bond brickwork in world space: bricks and mortar of the parameters' colours, the
/// mortar rougher. The renderer's material frame around it does the rest (lights, shadows,
/// decals, MSAA, every path).
#[shader_dsl::material(params = Bricks, uses(engine_shader_lib::patterns))]
pub mod bricks {
    /// The brickwork's parameters.
    pub struct Bricks {
        pub brick: Vec4,
        pub mortar: Vec4,
        /// Brick width and height, metres.
        pub size: Vec2,
        /// Joint width, metres.
        pub joint: f32,
        pub pad: f32,
    }

    fn surface(point: MaterialPoint, params: Bricks) -> Surface {
        let inside = brick_mask(point.world, point.normal, params.size, params.joint);
        let colour = params.mortar.xyz() + (params.brick.xyz() - params.mortar.xyz()) * inside;
        pattern_surface(point, colour * point.color.xyz(), 0.9 - 0.3 * inside)
    }
}
