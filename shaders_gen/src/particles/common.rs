//! What every particle kernel shares: the emitter and particle records, and the seeded hash that
//! makes a particle's birth depend only on (seed, emitter, spawn index), so the GPU simulation
//! and the CPU one in `renderer::particles::reference` agree particle for particle.

/// Particle records, emitter parameters and the seeded random numbers of a birth; a
/// particle's size and colour over its life; the atlas's Morton cells and packed regions; the
/// billboard's points and rounded normal; and the `Rg11b10Ufloat` packing of lit texels.
///
/// `random(seed, emitter, index, channel)` is a PCG hash chain; `renderer::particles::random`
/// computes the same integers on the CPU.
#[shader_dsl::library]
pub mod particle_common {
    /// One emitter as kernels read it. Sizes are world half-widths; colours linear RGB with
    /// alpha, interpolated over a particle's life.
    pub struct GpuEmitter {
        /// Centre of the spawn sphere.
        pub position: Vec3,
        pub spawn_radius: f32,
        /// Mean initial velocity (its direction is the spread cone's axis).
        pub velocity: Vec3,
        /// Cosine of the cone's half angle.
        pub spread_cos: f32,
        pub gravity: Vec3,
        /// Velocity lost per second, as a fraction.
        pub drag: f32,
        /// Lifetime range in seconds.
        pub lifetime: Vec2,
        /// Initial speed varies by ± this fraction.
        pub speed_jitter: f32,
        /// Layer of the particle texture array.
        pub texture: u32,
        /// Half-width at birth and at death.
        pub size: Vec2,
        /// Radiance the particle gives off unlit, as a multiple of its colour (sparks glow).
        pub emissive: f32,
        pub pad1: u32,
        pub color_start: Vec4,
        pub color_end: Vec4,
    }

    /// One particle slot. `alive` is 0 for a free slot (on the dead list).
    pub struct GpuParticle {
        pub position: Vec3,
        pub age: f32,
        pub velocity: Vec3,
        pub lifetime: f32,
        /// The emitter and the particle's spawn index within it: its identity.
        pub emitter: u32,
        pub index: u32,
        pub alive: u32,
        pub pad: u32,
    }

    /// The camera, lights and light grid as the particle lighting and drawing passes read
    /// them (one layout, so one buffer serves both).
    pub struct ParticleView {
        pub view: Mat4,
        pub view_projection: Mat4,
        /// Inverse projection: view depth of a depth-buffer value (soft particles).
        pub inv_projection: Mat4,
        /// The camera's unit right axis, in world space.
        pub right: Vec3,
        /// Lighting atlas side, texels.
        pub atlas_side: u32,
        /// The camera's unit up axis, in world space.
        pub up: Vec3,
        /// Punctual lights in `LIGHTS` (naive loop bound).
        pub light_count: u32,
        /// Eye position in world space.
        pub eye: Vec3,
        /// Directional lights at the start of `DIRECTIONAL`.
        pub directional_count: u32,
        /// Ambient radiance from straight up (the `pbr` library's `hemisphere_ambient`, at the
        /// particle's rounded normal, with `ambient_ground`).
        pub ambient_sky: Vec3,
        /// Tile size of the clustered grid, pixels.
        pub tile_size: u32,
        /// Ambient radiance from straight down.
        pub ambient_ground: Vec3,
        /// Tiles across and down.
        pub tiles: UVec2,
        /// Target size, pixels.
        pub screen: UVec2,
        /// Depth slices of the clustered grid.
        pub slices: u32,
        /// View depth where slice 1 starts.
        pub near: f32,
        /// View depth where the last slice starts.
        pub far: f32,
        /// View-depth distance over which a particle fades out in front of a surface (soft
        /// particles); 0 turns the fade off.
        pub soft_distance: f32,
        /// Samples a pixel of the frame (its MSAA count): how `particle_draw`'s `vis64`
        /// variants index the compute rasteriser's samples.
        pub samples: u32,
        /// Where view vectors point, homogeneous: `(eye, 1)`, or for an orthographic camera
        /// the view's +Z axis with `w` 0; the view vector at `p` is `normalize(xyz − p w)`.
        pub eye_homogeneous: Vec4,
    }

    /// PCG's output permutation of one LCG step: a well-mixed 32-bit hash.
    pub fn pcg(v: u32) -> u32 {
        let state = v * 747796405u32 + 2891336453u32;
        let word = ((state >> ((state >> 28u32) + 4u32)) ^ state) * 277803737u32;
        (word >> 22u32) ^ word
    }

    /// A number in `[0, 1)` for random `channel` of the birth of particle `index` of `emitter`.
    pub fn random(seed: u32, emitter: u32, index: u32, channel: u32) -> f32 {
        let h = pcg(seed ^ pcg(emitter ^ pcg(index ^ pcg(channel))));
        (h >> 8u32) as f32 * (1.0 / 16777216.0)
    }

    /// How far through its life a particle is, 0 to 1.
    pub fn life(p: GpuParticle) -> f32 {
        (p.age / p.lifetime).saturate()
    }

    /// A particle's world half-width now.
    pub fn half_width(e: GpuEmitter, p: GpuParticle) -> f32 {
        e.size.x + (e.size.y - e.size.x) * life(p)
    }

    /// A particle's colour (linear RGB, alpha) now.
    pub fn tint(e: GpuEmitter, p: GpuParticle) -> Vec4 {
        e.color_start.lerp(e.color_end, life(p))
    }

    /// Cell (x, y) of Morton index `m`: the even bits are x, the odd bits y.
    pub fn morton_cell(m: u32) -> UVec2 {
        let mut x = 0u32;
        let mut y = 0u32;
        for bit in 0u32..16u32 {
            x = x | (((m >> (2u32 * bit)) & 1u32) << bit);
            y = y | (((m >> (2u32 * bit + 1u32)) & 1u32) << bit);
        }
        UVec2::new(x, y)
    }

    /// A region as `particle_atlas` packs it: corner `x | y << 12` in texels, side class
    /// `<< 24`. Returns `(x, y, side)`.
    pub fn region_rect(packed: u32) -> UVec3 {
        UVec3::new(
            packed & 0xFFFu32,
            (packed >> 12u32) & 0xFFFu32,
            2u32 << (packed >> 24u32),
        )
    }

    /// The world point at `uv` of a camera-facing billboard (`uv` 0 at its top-left corner,
    /// 1 at its bottom-right; `right` and `up` the camera's unit axes).
    pub fn billboard_point(centre: Vec3, half_width: f32, uv: Vec2, right: Vec3, up: Vec3) -> Vec3 {
        let q = uv * 2.0 - 1.0;
        centre + (right * q.x - up * q.y) * half_width
    }

    /// The rounded normal at `uv` of a billboard seen along `-toward_eye`: that of a sphere
    /// bulging towards the eye, lying in the billboard's plane at and beyond its rim. Lighting
    /// with it shades a puff as a ball, not a card.
    pub fn billboard_normal(uv: Vec2, right: Vec3, up: Vec3, toward_eye: Vec3) -> Vec3 {
        let q = uv * 2.0 - 1.0;
        let bulge = (1.0 - q.dot(q)).max(0.0).sqrt();
        (right * q.x - up * q.y + toward_eye * bulge).normalize()
    }

    /// Packs linear RGB (negative values clamp to 0) into `Rg11b10Ufloat`'s bits: red in bits
    /// 0–10, green 11–21, blue 22–31, each an unsigned float with a 5-bit exponent, rounded to
    /// nearest; values past the largest finite one (65024) clamp to it.
    pub fn pack_rg11b10(c: Vec3) -> u32 {
        pack_ufloat(c.x, 6u32)
            | (pack_ufloat(c.y, 6u32) << 11u32)
            | (pack_ufloat(c.z, 5u32) << 22u32)
    }

    /// One unsigned float of `mantissa` bits and a 5-bit exponent (bias 15), rounded to
    /// nearest; small values flush to 0.
    pub fn pack_ufloat(v: f32, mantissa: u32) -> u32 {
        let clamped = v.clamp(0.0, 65024.0);
        let drop = 23u32 - mantissa;
        // Rounding by adding half the last kept bit; a carry moves into the exponent as it should.
        let bits = clamped.to_bits() + (1u32 << (drop - 1u32));
        let exponent = (bits >> 23u32) & 0xFFu32;
        let mut packed = 0u32;
        if exponent > 112u32 {
            let e = (exponent - 112u32).min(30u32);
            let m = select(
                exponent - 112u32 > 30u32,
                (1u32 << mantissa) - 1u32,
                (bits & 0x7FFFFFu32) >> drop,
            );
            packed = (e << mantissa) | m;
        }
        packed
    }
}
