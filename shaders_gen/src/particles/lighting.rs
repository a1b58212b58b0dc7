//! Particle lighting at a point, written once: the atlas kernel (`particle_light`) runs it per
//! atlas texel, the particle draw (`particle_draw`) per pixel on its reference path.

/// The particle frame group's contract and the particles' light response: `VIEW` (group 0,
/// binding 0, the [`ParticleView`] both passes share, one buffer), the lights and lists of
/// `light_lists` (bindings 1–4), and `particle_lighting`, ambient plus every light that reaches
/// a point of a billboard, shadowed, with the `pbr` library's half-Lambert `particle_light`.
///
/// `list` picks the lights: `0` every light (`LIGHTS[0..light_count]`), `2` the clustered list
/// of the froxel the point projects into (its pixel clamped to the screen, the same
/// `light_grid` lookup as forward shading). The lists must cover every depth slice in front of
/// the opaque surfaces (the culling pass lists every slice when particles are drawn).
#[shader_dsl::library(
    axes(list: u32 = [0, 2]),
    uses(
        crate::particles::common::particle_common,
        crate::shared::pbr,
        crate::shared::light_lists,
        crate::shared::light_grid,
        crate::shared::shadow_atlas,
    ),
)]
pub mod particle_lighting {
    #[uniform(group = 0, binding = 0)]
    static VIEW: ParticleView;

    /// One light's shadowed response at `p` (no normal offset: a billboard has no geometry
    /// behind it to offset from).
    fn particle_contribution(light: GpuLight, p: Vec3, n: Vec3, depth: f32, dither: f32) -> Vec3 {
        let radiance = particle_light(light, p, n);
        let mut visibility = 1.0;
        if radiance.x + radiance.y + radiance.z > 0.0 {
            visibility =
                shadow_visibility(light.shadow, light.position, p, Vec3::ZERO, depth, dither);
        }
        radiance * visibility
    }

    /// The `GRID` cell of world point `p` at view depth `depth`: the froxel its projection
    /// falls in, the pixel clamped to the screen.
    fn froxel_of(p: Vec3, depth: f32) -> u32 {
        let clip = VIEW.view_projection * p.extend(1.0);
        let ndc = clip.xy() / clip.w.max(1.0e-6);
        let size = VIEW.screen.as_vec2();
        let at = Vec2::new(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * size;
        let px = at.clamp(Vec2::ZERO, size - 1.0).floor().as_uvec2();
        let slice = slice_of(depth.max(1.0e-6), VIEW.near, VIEW.far, VIEW.slices);
        froxel_cell(px, slice, VIEW.tile_size, VIEW.tiles)
    }

    /// Ambient plus every light of `p`'s froxel (or every light), shadowed, at a billboard
    /// point `p` with rounded normal `n`; `dither` drives the cascade transition.
    pub fn particle_lighting(p: Vec3, n: Vec3, dither: f32) -> Vec3 {
        let depth = -(VIEW.view * p.extend(1.0)).z;
        let mut color = hemisphere_ambient(VIEW.ambient_sky, VIEW.ambient_ground, n);
        for i in 0u32..VIEW.directional_count {
            color += particle_contribution(DIRECTIONAL[i], p, n, depth, dither);
        }
        if list == 0 {
            for i in 0u32..VIEW.light_count {
                color += particle_contribution(LIGHTS[i], p, n, depth, dither);
            }
        } else {
            let range = GRID[froxel_of(p, depth)];
            for j in 0u32..range.y {
                color += particle_contribution(LIGHTS[INDICES[range.x + j]], p, n, depth, dither);
            }
        }
        color
    }
}
