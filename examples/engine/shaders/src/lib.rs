//! An engine's shader module: it uses its own library crate's `surface` library and the
//! renderer's PBR library, over an axis of its own.

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
