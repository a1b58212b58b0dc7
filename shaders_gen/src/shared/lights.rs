//! The frame's lights as every lit pass reads them: the light records, their bounding spheres
//! and the culled lists (binding contracts of group 0, bindings 1–4), and the one shadowed light response of a
//! surface point, written once for forward shading, the TBDR kernel and the light volumes.

/// The frame's light records, group 0: `LIGHTS` (binding 1) the punctual lights, point and
/// spot, in the order the culled lists index them; `DIRECTIONAL` (binding 2) the directional
/// lights. How many of each are live is the using pass's own parameter (a count in its uniform).
///
/// Every lit pass binds them through this library's builder part (`light_set::Group0`), so the
/// host hands over the same two buffers by name everywhere.
#[shader_dsl::library(uses(crate::shared::pbr))]
pub mod light_set {
    #[storage(group = 0, binding = 1)]
    static LIGHTS: [GpuLight];
    #[storage(group = 0, binding = 2)]
    static DIRECTIONAL: [GpuLight];
}

/// The punctual lights' bounding spheres, group 0: `SPHERES` (binding 3), world-space centre
/// and radius of each light in `LIGHTS` order, for the deferred paths that test lights
/// themselves (the TBDR kernel's tiles, the light volumes' cubes). A pass reads these or the
/// culled lists of `light_lists` (which take binding 3 for `GRID`), never both.
#[shader_dsl::library(uses(crate::shared::light_set))]
pub mod light_spheres {
    #[storage(group = 0, binding = 3)]
    static SPHERES: [Vec4];
}

/// The light culling kernels' output as the shading passes read it, group 0: `GRID`
/// (binding 3) holds `(offset, count)` per cell (a screen tile, or a froxel: a tile in one depth
/// slice, as `light_grid` numbers them), `INDICES` (binding 4) the lights of every cell, each an
/// index into `LIGHTS` (some passes also keep decal lists in further sections of the grid).
///
/// The axis `list` says which lists a variant reads: `0` none (it loops over every light, and
/// the two bindings are not declared), `1` the tiled lists, `2` the clustered lists.
#[shader_dsl::library(axes(list: u32 = [0, 1, 2]), uses(crate::shared::light_set))]
pub mod light_lists {
    #[storage(group = 0, binding = 3)]
    #[when(list > 0)]
    static GRID: [UVec2];
    #[storage(group = 0, binding = 4)]
    #[when(list > 0)]
    static INDICES: [u32];
}

/// The light loops' one response: the radiance a light reflects from a surface point towards
/// the eye (the `pbr` library's `shade_light`), times the shadow atlas's visibility of the point
/// from that light. Forward shading, the TBDR kernel and the light volumes all call
/// `light_contribution`, so the paths cannot drift apart.
#[shader_dsl::library(uses(crate::shared::pbr, crate::shared::shadow_atlas))]
pub mod surface_light {
    /// A shaded surface point, as a light loop takes it.
    pub struct LitPoint {
        /// World-space position.
        pub p: Vec3,
        /// Unit shading normal (normal-mapped).
        pub n: Vec3,
        /// Unit vector towards the eye.
        pub v: Vec3,
        pub albedo: Vec3,
        pub metallic: f32,
        pub roughness: f32,
        /// Unit normal of the geometry (not normal-mapped): the shadow lookup's normal offset.
        pub geometric_normal: Vec3,
        /// Camera view depth: picks the directional light's cascade.
        pub view_depth: f32,
        /// Screen-space noise in `[0, 1)` for the dithered cascade transition.
        pub dither: f32,
    }

    /// Radiance `light` reflects from `s` towards the eye, shadowed. The shadow lookup runs only
    /// where the light reaches the surface at all: a listed light out of range or behind the
    /// surface costs no atlas taps.
    pub fn light_contribution(light: GpuLight, s: LitPoint) -> Vec3 {
        let radiance = shade_light(light, s.p, s.n, s.v, s.albedo, s.metallic, s.roughness);
        let mut visibility = 1.0;
        if radiance.x + radiance.y + radiance.z > 0.0 {
            visibility = shadow_visibility(
                light.shadow,
                light.position,
                s.p,
                s.geometric_normal,
                s.view_depth,
                s.dither,
            );
        }
        radiance * visibility
    }
}
