//! Lighting the particle atlas: one thread per texel of the cells `particle_atlas` used this
//! frame. A texel finds its particle from its Morton cell (the class ranges and `OWNERS`),
//! reconstructs its world point on the particle's billboard and its rounded normal, and sums
//! ambient and every light of its froxel with the particles' half-Lambert response, shadowed.

/// Atlas lighting (DOOM 2016's particle lighting atlas): lighting is computed once per atlas
/// texel instead of once per covered pixel of every overlapping particle.
///
/// `list` picks the lights of a texel: `0` every light (`LIGHTS[0..light_count]`), `2` the
/// clustered list of the froxel its point projects into (pixel clamped to the screen, the
/// same `light_grid` lookup as forward shading). The lists must cover every depth slice in
/// front of the opaque surfaces (the culling pass lists every slice when particles are drawn).
/// Not scalarized: one particle's texels span several froxels.
///
/// Output: `LIT[y · atlas_side + x]`, the `Rg11b10Ufloat` bits of the texel's irradiance-like
/// response (the draw multiplies it by the particle's colour and texture); the host copies the
/// buffer into the atlas texture (that format has no storage binding).
#[shader_dsl::shader(
    axes(list: u32 = [0, 2] => "list"),
    uses(
        crate::particles::common::particle_common,
        crate::shared::pbr,
        crate::shared::light_grid,
        crate::shared::shadow_atlas,
    ),
)]
pub mod particle_light {
    pub const WORKGROUP: u32 = 64;
    /// Workgroups in one row of the indirect dispatch (`particle_atlas::LIGHT_ROW_GROUPS`).
    pub const ROW_GROUPS: u32 = 32768;
    /// Side classes (`particle_atlas::CLASSES`).
    const CLASSES: u32 = 5;

    #[uniform(group = 0, binding = 0)]
    static VIEW: ParticleView;
    #[storage(group = 0, binding = 1)]
    static LIGHTS: [GpuLight];
    #[storage(group = 0, binding = 2)]
    static DIRECTIONAL: [GpuLight];
    #[storage(group = 0, binding = 3)]
    #[when(list > 0)]
    static GRID: [UVec2];
    #[storage(group = 0, binding = 4)]
    #[when(list > 0)]
    static INDICES: [u32];

    #[storage(group = 1, binding = 0)]
    static EMITTERS: [GpuEmitter];
    #[storage(group = 1, binding = 1)]
    static PARTICLES: [GpuParticle];
    #[storage(group = 1, binding = 2)]
    static STATE: [u32];
    #[storage(group = 1, binding = 3)]
    static OWNERS: [u32];
    #[storage(group = 1, binding = 4, read_write)]
    static LIT: [u32];

    /// One light's shadowed response at `p`.
    fn particle_contribution(light: GpuLight, p: Vec3, n: Vec3, depth: f32, dither: f32) -> Vec3 {
        let radiance = particle_light(light, p, n);
        let mut visibility = 1.0;
        if radiance.x + radiance.y + radiance.z > 0.0 {
            visibility =
                shadow_visibility(light.shadow, light.position, p, Vec3::ZERO, depth, dither);
        }
        radiance * visibility
    }

    /// Ambient plus every light of `p`'s froxel (or every light), shadowed.
    fn particle_lighting(p: Vec3, n: Vec3, dither: f32) -> Vec3 {
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
            let clip = VIEW.view_projection * p.extend(1.0);
            let ndc = clip.xy() / clip.w.max(1.0e-6);
            let size = VIEW.screen.as_vec2();
            let at = Vec2::new(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * size;
            let px = at.clamp(Vec2::ZERO, size - 1.0).floor().as_uvec2();
            let slice = slice_of(depth.max(1.0e-6), VIEW.near, VIEW.far, VIEW.slices);
            let range = GRID[froxel_cell(px, slice, VIEW.tile_size, VIEW.tiles)];
            for j in 0u32..range.y {
                color += particle_contribution(LIGHTS[INDICES[range.x + j]], p, n, depth, dither);
            }
        }
        color
    }

    #[compute(workgroup_size(64, 1, 1))]
    pub fn light_atlas(#[builtin(global_invocation_id)] gid: UVec3) {
        let t = gid.y * (ROW_GROUPS * WORKGROUP) + gid.x;
        if t < STATE[16] * 4u32 {
            let cell = t >> 2u32;
            // The class whose cell range holds `cell`: bases fall as classes grow, and an
            // empty class starts where the next smaller one does.
            let mut class = CLASSES;
            for c in 0u32..CLASSES {
                if class == CLASSES && cell >= STATE[10u32 + c] {
                    class = c;
                }
            }
            let within = cell - STATE[10u32 + class];
            let slot = OWNERS[STATE[19u32 + class] + (within >> (2u32 * class))];
            let side = 2u32 << class;
            let sub = UVec2::new(t & 1u32, (t >> 1u32) & 1u32);
            let local = morton_cell(within & ((1u32 << (2u32 * class)) - 1u32)) * 2u32 + sub;
            let texel = morton_cell(cell) * 2u32 + sub;
            let particle = PARTICLES[slot];
            let emitter = EMITTERS[particle.emitter];
            let uv = (local.as_vec2() + 0.5) / side as f32;
            let eye = VIEW.eye_homogeneous;
            let toward_eye = (eye.xyz() - particle.position * eye.w).normalize();
            let p = billboard_point(
                particle.position,
                half_width(emitter, particle),
                uv,
                VIEW.right,
                VIEW.up,
            );
            let n = billboard_normal(uv, VIEW.right, VIEW.up, toward_eye);
            let dither = dither_noise(texel.as_vec2());
            LIT[texel.y * VIEW.atlas_side + texel.x] =
                pack_rg11b10(particle_lighting(p, n, dither));
        }
    }
}
