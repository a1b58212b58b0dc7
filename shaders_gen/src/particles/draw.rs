//! Drawing particles: camera-facing billboards in back-to-front order (the sorted keys), blended
//! over the lit scene, lit either from the lighting atlas (bicubic) or per pixel (the
//! reference), faded where they meet a surface.

/// The particle draw. One instance per visible particle in back-to-front order (instance `i`
/// draws slot `KEYS[i].y`; the indirect draw's instance count is the visible count), six
/// vertices a billboard.
///
/// `atlas` picks the lighting: the atlas, the particle's region of `LIGHT_ATLAS`, B-spline
/// bicubic (four bilinear taps, each clamped half a texel inside the region so no neighbour
/// bleeds in); or, without it, per pixel with `particle_lighting`, the same half-Lambert
/// response, shadows and ambient as `particle_light` computes per atlas texel (the reference
/// path), over every light (`list` 0) or the clustered lists (`list` 2). The atlas variants read
/// no list (`list` 0 only).
///
/// The colour is the particle's tint times its sprite (`SPRITES`, a layer per texture) times
/// the lighting plus its emitter's `emissive`, premultiplied by alpha (blend: one, one minus
/// source alpha).
///
/// Depth: the fragment finds the samples of its pixel whose surface lies beyond the particle
/// (`visible_samples`), is discarded where there are none, and fades alpha to 0 as the
/// particle's view depth nears the farthest of those surfaces (soft particles,
/// `soft_distance`; 0 turns the fade off). The surfaces' depths are a copy of the pre-Z depth
/// (`DEPTH`, or `DEPTH_MS` with `msaa`), and the pipeline's depth test (read-only, `Less`,
/// against the pre-Z depth attached read-only) keeps occlusion per sample (`fs_particle`). With
/// `vis64` they are the compute rasteriser's samples (`VIS64`, `VIEW.samples` a pixel whatever
/// the frame's MSAA, so `msaa` stays false) and there is no depth target: `fs_particle_vis64`
/// scales its premultiplied colour by the share of the pixel's samples it is in front of and
/// draws into every sample it covers. Where the samples under it hold the same colour (the
/// transparent overlay it draws into with MSAA, or one sample) that resolves to what drawing
/// into the visible samples alone would; it writes no `sample_mask`, whose SPIR-V naga 30
/// writes invalidly (`crate::shader`'s documentation). The sprite is sampled before the
/// discard, so its derivatives see the whole quad.
#[shader_dsl::shader(
    axes(
        atlas: bool = [false, true] => "atlas",
        list: u32 = [0, 2] => "list",
        msaa: bool = [false, true] => "ms",
        vis64: bool = [false, true] => "vis64",
    ),
    exclude(atlas && list == 2),
    exclude(vis64 && msaa),
    uses(
        crate::particles::lighting::particle_lighting,
        crate::visibility::samples64::vis64_sample,
    ),
)]
pub mod particle_draw {
    pub struct ParticleVarying {
        /// Invariant: the overlay's eraser (`overlay_erase`) draws the same billboards with
        /// another fragment stage and must cover exactly the samples this draw covered.
        #[builtin(position)]
        #[invariant]
        pub clip: Vec4,
        #[location(0)]
        pub uv: Vec2,
        #[location(1)]
        pub tint: Vec4,
        #[location(2)]
        pub world: Vec3,
        #[location(3)]
        pub view_depth: f32,
        #[location(4)]
        #[interpolate(flat)]
        pub region: u32,
        #[location(5)]
        #[interpolate(flat)]
        pub layer: u32,
        #[location(6)]
        #[interpolate(flat)]
        pub toward_eye: Vec3,
        #[location(7)]
        #[interpolate(flat)]
        pub emissive: f32,
    }

    /// Which samples of a pixel a fragment is in front of, and the farthest surface among them.
    struct Visible {
        mask: u32,
        surface: f32,
    }

    pub struct ParticleOut {
        #[location(0)]
        pub color: Vec4,
    }

    #[texture(group = 0, binding = 5)]
    #[when(!msaa && !vis64)]
    static DEPTH: TextureDepth2d;
    #[texture(group = 0, binding = 5)]
    #[when(msaa)]
    static DEPTH_MS: TextureDepthMultisampled2d;
    /// The compute rasteriser's samples (`vis_compute_raster`'s `VIS64`) as `(low, high)` word
    /// pairs, `(y × width + x) × samples + s`: `(!depth_bits << 32) | !id`, 0 where no
    /// triangle covered the sample.
    #[storage(group = 0, binding = 5)]
    #[when(vis64)]
    static VIS64: [UVec2];

    #[storage(group = 1, binding = 0)]
    static EMITTERS: [GpuEmitter];
    #[storage(group = 1, binding = 1)]
    static PARTICLES: [GpuParticle];
    #[storage(group = 1, binding = 2)]
    static REGIONS: [u32];
    #[storage(group = 1, binding = 3)]
    static KEYS: [UVec2];
    #[texture(group = 1, binding = 4)]
    #[when(atlas)]
    static LIGHT_ATLAS: Texture2d<f32>;
    #[sampler(group = 1, binding = 5)]
    #[when(atlas)]
    static ATLAS_SAMPLER: Sampler;
    #[texture(group = 1, binding = 6)]
    static SPRITES: Texture2dArray<f32>;
    #[sampler(group = 1, binding = 7)]
    static SPRITE_SAMPLER: Sampler;

    #[vertex]
    pub fn vs_particle(
        #[builtin(vertex_index)] vertex: u32,
        #[builtin(instance_index)] instance: u32,
    ) -> ParticleVarying {
        let slot = KEYS[instance].y;
        let particle = PARTICLES[slot];
        let emitter = EMITTERS[particle.emitter];
        // Two triangles over corners 0 (0,0), 1 (1,0), 2 (0,1), 3 (1,1): (0, 1, 2) and
        // (2, 1, 3), the second's corners packed two bits each in 0b11_01_10.
        let corner = select(
            vertex < 3u32,
            vertex,
            (0x36u32 >> (2u32 * (vertex - 3u32))) & 3u32,
        );
        let uv = Vec2::new((corner & 1u32) as f32, (corner >> 1u32) as f32);
        let world = billboard_point(
            particle.position,
            half_width(emitter, particle),
            uv,
            VIEW.right,
            VIEW.up,
        );
        ParticleVarying {
            clip: VIEW.view_projection * world.extend(1.0),
            uv,
            tint: tint(emitter, particle),
            world,
            view_depth: -(VIEW.view * world.extend(1.0)).z,
            region: REGIONS[slot],
            layer: emitter.texture,
            toward_eye: (VIEW.eye_homogeneous.xyz() - particle.position * VIEW.eye_homogeneous.w)
                .normalize(),
            emissive: emitter.emissive,
        }
    }

    /// The atlas lighting at `uv` of the region `packed`: B-spline bicubic from four bilinear
    /// taps (Sigg and Hadwiger's weights folded into tap positions), each tap clamped half a
    /// texel inside the region.
    pub fn atlas_bicubic(packed: u32, uv: Vec2) -> Vec3 {
        let rect = region_rect(packed);
        let side = rect.z as f32;
        let st = uv * side - 0.5;
        let i = st.floor();
        let f = st - i;
        let f2 = f * f;
        let f3 = f2 * f;
        let w0 = (Vec2::ONE - f) * (Vec2::ONE - f) * (Vec2::ONE - f) / 6.0;
        let w1 = (f3 * 3.0 - f2 * 6.0 + 4.0) / 6.0;
        let w2 = (f3 * -3.0 + f2 * 3.0 + f * 3.0 + 1.0) / 6.0;
        let w3 = f3 / 6.0;
        let g0 = w0 + w1;
        let g1 = w2 + w3;
        let lo = Vec2::splat(0.5);
        let hi = Vec2::splat(side - 0.5);
        let c0 = (i - 0.5 + w1 / g0).clamp(lo, hi);
        let c1 = (i + 1.5 + w3 / g1).clamp(lo, hi);
        let corner = rect.xy().as_vec2();
        let inv = 1.0 / VIEW.atlas_side as f32;
        let t00 = LIGHT_ATLAS
            .sample_level(ATLAS_SAMPLER, (corner + Vec2::new(c0.x, c0.y)) * inv, 0.0)
            .xyz();
        let t10 = LIGHT_ATLAS
            .sample_level(ATLAS_SAMPLER, (corner + Vec2::new(c1.x, c0.y)) * inv, 0.0)
            .xyz();
        let t01 = LIGHT_ATLAS
            .sample_level(ATLAS_SAMPLER, (corner + Vec2::new(c0.x, c1.y)) * inv, 0.0)
            .xyz();
        let t11 = LIGHT_ATLAS
            .sample_level(ATLAS_SAMPLER, (corner + Vec2::new(c1.x, c1.y)) * inv, 0.0)
            .xyz();
        (t00 * g0.x + t10 * g1.x) * g0.y + (t01 * g0.x + t11 * g1.x) * g1.y
    }

    /// The samples of `pixel` whose opaque surface lies beyond view depth `depth` (bit per
    /// sample) and the farthest such surface's view depth.
    fn visible_samples(pixel: UVec2, depth: f32) -> Visible {
        let mut mask = 0u32;
        let mut surface = 0.0;
        let mut samples = 1u32;
        if msaa {
            samples = DEPTH_MS.num_samples();
        } else if vis64 {
            samples = VIEW.samples;
        }
        for s in 0u32..samples {
            let mut d = 1.0;
            if vis64 {
                d = vis64_depth(VIS64[(pixel.y * VIEW.screen.x + pixel.x) * samples + s]);
            } else if msaa {
                d = DEPTH_MS.load(pixel, s);
            } else {
                d = DEPTH.load(pixel, 0u32);
            }
            let behind = view_depth(VIEW.inv_projection, d);
            if depth < behind {
                mask = mask | (1u32 << s);
                surface = surface.max(behind);
            }
        }
        Visible { mask, surface }
    }

    /// The premultiplied colour of the particle at `input` with its `sprite` texel, faded in
    /// front of `visible`'s farthest surface.
    fn particle_color(input: ParticleVarying, visible: Visible, sprite: Vec4) -> Vec4 {
        let mut lighting = Vec3::ZERO;
        if atlas {
            lighting = atlas_bicubic(input.region, input.uv);
        } else {
            let n = billboard_normal(input.uv, VIEW.right, VIEW.up, input.toward_eye);
            lighting = particle_lighting(input.world, n, dither_noise(input.clip.xy()));
        }
        let mut fade = 1.0;
        if VIEW.soft_distance > 0.0 {
            fade = ((visible.surface - input.view_depth) / VIEW.soft_distance).saturate();
        }
        let alpha = input.tint.w * sprite.w * fade;
        let color = input.tint.xyz() * sprite.xyz() * (lighting + input.emissive) * alpha;
        color.extend(alpha)
    }

    #[fragment]
    #[when(!vis64)]
    pub fn fs_particle(input: ParticleVarying) -> ParticleOut {
        let sprite = SPRITES.sample(SPRITE_SAMPLER, input.uv, input.layer);
        let visible = visible_samples(input.clip.xy().floor().as_uvec2(), input.view_depth);
        if visible.mask == 0u32 {
            discard();
        }
        ParticleOut {
            color: particle_color(input, visible, sprite),
        }
    }

    #[fragment]
    #[when(vis64)]
    pub fn fs_particle_vis64(input: ParticleVarying) -> ParticleOut {
        let sprite = SPRITES.sample(SPRITE_SAMPLER, input.uv, input.layer);
        let visible = visible_samples(input.clip.xy().floor().as_uvec2(), input.view_depth);
        if visible.mask == 0u32 {
            discard();
        }
        let share = visible.mask.count_ones() as f32 / VIEW.samples as f32;
        ParticleOut {
            color: particle_color(input, visible, sprite) * share,
        }
    }
}
