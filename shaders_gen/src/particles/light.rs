//! Lighting the particle atlas: one thread per texel of the cells `particle_atlas` used this
//! frame. A texel finds its particle from its Morton cell (the class ranges and `OWNERS`),
//! reconstructs its world point on the particle's billboard and its rounded normal, and sums
//! ambient and every light of its froxel with the particles' half-Lambert response, shadowed.

/// Atlas lighting (DOOM 2016's particle lighting atlas): lighting is computed once per atlas
/// texel instead of once per covered pixel of every overlapping particle.
///
/// `list` picks the lights of a texel (`particle_lighting`'s axis): `0` every light, `2` the
/// clustered list of its froxel. Not scalarized: one particle's texels span several froxels.
///
/// Output: `LIT[y · atlas_side + x]`, the `Rg11b10Ufloat` bits of the texel's irradiance-like
/// response (the draw multiplies it by the particle's colour and texture); the host copies the
/// buffer into the atlas texture (that format has no storage binding).
#[shader_dsl::shader(
    axes(list: u32 = [0, 2] => "list"),
    uses(crate::particles::lighting::particle_lighting),
)]
pub mod particle_light {
    pub const WORKGROUP: u32 = 64;
    /// Workgroups in one row of the indirect dispatch (`particle_atlas::LIGHT_ROW_GROUPS`).
    pub const ROW_GROUPS: u32 = 32768;
    /// Side classes (`particle_atlas::CLASSES`).
    const CLASSES: u32 = 5;

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
