//! Tile-based deferred shading: one workgroup per screen tile reads the G-buffer, bounds the
//! tile's depth, culls the lights in workgroup memory and shades, per sample where the samples
//! of a pixel differ.

/// Tile-based deferred shading (TBDR) with per-sample MSAA, after reference 000 (Lauritzen's
/// "Deferred Rendering for Current and Future Rendering Pipelines"): one dispatch, one
/// workgroup of `tile`×`tile` invocations per tile, one invocation per pixel.
///
/// 1. **Depth bounds.** Every sample of the tile's pixels (sky, depth 1, excluded) folds into
///    the tile's depth range, the opaque range of `tile_cull`.
/// 2. **Edges.** A pixel is an *edge* when any of its samples differs from sample 0: one is sky
///    and the other not, the sample lies off the plane of sample 0 (its point and geometric
///    normal) by more than `depth_edge` of its view depth, the angle between their shading
///    normals passes `acos(normal_edge)`, or albedo, metalness, roughness or base radiance
///    differ by more than `material_edge` (the radiance relative to `1 + ` its size). Only edge
///    pixels are shaded per sample.
/// 3. **Light culling** in workgroup memory, with no cap and no drop: the lights are taken in
///    chunks of `CHUNK`; each chunk's lights are tested against the tile's frustum (the side
///    planes and the bounding box between the depth bounds, `light_grid`'s tests, as
///    `tile_cull`'s) into `LIST`, which holds a whole chunk, then shaded, then the next chunk
///    replaces them. With `scalarize` the append is one atomic per subgroup (ballot, exclusive
///    add) and list entries are read as subgroup-uniform values.
/// 4. **Shading** of sample 0 of every pixel, with the forward pass's light loop: `pbr`'s
///    `shade_light` and `shadow_atlas`'s `shadow_visibility`, the base radiance (ambient and
///    emissive, from the G-buffer) and every directional light. A pixel whose samples agree is
///    shaded at its centre, at the view depth the G-buffer stored for sample 0, where the
///    forward pass shades it; a sample of an edge pixel at its own point, where the ray through
///    its standard sample position meets its fragment's plane.
/// 5. **Per-sample shading** of the edge pixels' other samples: inline (each invocation shades
///    its own pixel's samples) or, with `defer`, "defer per sample": the edge pixels go to a
///    tile list, and every invocation of the tile drains `(pixel, sample)` items from it, so a
///    few edge pixels do not hold the whole tile up. Item results are gathered back to their
///    pixels through workgroup memory, one round of `tile`² items at a time.
/// 6. The resolved HDR colour (the mean of the samples, sample 0 standing for all of a
///    non-edge pixel) is stored to `HDR_OUT`. With `show_frequency`, edge pixels are drawn red
///    (the shading-frequency view); with `record_edges`, each edge pixel sets its bit in
///    `EDGE_BITS` (row-major, 32 pixels a word).
///
/// The G-buffer's bindings, its samples, the edge test of step 2 and the shading points of
/// steps 4 and 5 are the `tbdr_gbuffer` library's (`gbuffer_read.rs`).
///
/// `capture_gbuffer` copies every sample of the G-buffer to `CAPTURE` (14 words per sample:
/// depth, then the four targets' texels), so tools and tests can check the edge detector on
/// the CPU.
#[shader_dsl::shader(
    axes(
        tile: u32 = [8, 16] => "t",
        msaa: u32 = [1, 2, 4, 8],
        scalarize: bool = [false, true] => "scalar",
        defer: bool = [false, true] => "defer",
    ),
    exclude(msaa == 1 && defer),
    requires(subgroup = scalarize),
    uses(
        crate::deferred::gbuffer_read::tbdr_gbuffer,
        crate::shared::light_spheres,
        crate::shared::pbr,
        crate::shared::light_grid,
        crate::shared::shadow_atlas,
        crate::shared::octahedral,
    ),
)]
pub mod tbdr {
    /// Invocations (pixels) per tile.
    pub const TILE_THREADS: u32 = tile * tile;
    /// Lights culled into workgroup memory at a time (the whole chunk fits, so none is dropped).
    pub const CHUNK: u32 = 1024;
    /// Words of `CAPTURE` per sample.
    pub const CAPTURE_WORDS: u32 = 14;
    const INFINITY_BITS: u32 = 0x7f80_0000;

    #[texture(group = 0, binding = 11)]
    static HDR_OUT: StorageTexture2d<Rgba16Float, Write>;
    #[storage(group = 0, binding = 12, read_write)]
    static EDGE_BITS: [Atomic<u32>];
    #[storage(group = 0, binding = 13, read_write)]
    static CAPTURE: [f32];

    #[workgroup]
    static RANGE_MIN: Atomic<u32>;
    #[workgroup]
    static RANGE_MAX: Atomic<u32>;
    #[workgroup]
    static LIST_COUNT: Atomic<u32>;
    #[workgroup]
    static LIST: [u32; CHUNK];
    #[workgroup]
    static EDGE_COUNT: Atomic<u32>;
    /// Edge pixels of the tile (invocation indices), for `defer`.
    #[workgroup]
    static EDGES: [u32; TILE_THREADS];
    /// One round of deferred item colours, for `defer`.
    #[workgroup]
    static ITEM_COLOR: [Vec3; TILE_THREADS];

    /// What does not depend on the culled lights: the sky, or the base radiance and every
    /// directional light.
    fn unculled(s: Shading) -> Vec3 {
        let mut color = PARAMS.sky;
        if !s.sky {
            color = s.base;
            for i in 0u32..PARAMS.directional_count {
                color += light_contribution(DIRECTIONAL[i], s.point);
            }
        }
        color
    }

    /// The first `n` lights of `LIST` at `s` (nothing for sky).
    fn listed(s: Shading, n: u32) -> Vec3 {
        let mut color = Vec3::ZERO;
        if !s.sky {
            for j in 0u32..n {
                let mut index = LIST[j];
                if scalarize {
                    index = subgroup_broadcast_first(index);
                }
                color += light_contribution(LIGHTS[index], s.point);
            }
        }
        color
    }

    /// Appends `light` to `LIST` when `hit`: one atomic per light, or with `scalarize` one per
    /// subgroup, each lane taking its rank among the subgroup's hits.
    fn list_append(hit: bool, light: u32, lid: u32) {
        if scalarize {
            let one = select(hit, 1u32, 0u32);
            let hits = subgroup_add(one);
            let rank = subgroup_exclusive_add(one);
            let mut base = 0u32;
            if subgroup_broadcast_first(lid) == lid && hits > 0u32 {
                base = LIST_COUNT.fetch_add(hits);
            }
            base = subgroup_broadcast_first(base);
            if hit {
                LIST[base + rank] = light;
            }
        } else if hit {
            LIST[LIST_COUNT.fetch_add(1u32)] = light;
        }
    }

    /// Tests lights `start..start + count` against the tile's frustum into `LIST`.
    fn cull_chunk(
        start: u32,
        count: u32,
        lid: u32,
        sides: SidePlanes,
        rays: TileRays,
        near: f32,
        far: f32,
    ) {
        let mut i = lid;
        while i < count {
            let sphere = SPHERES[start + i];
            let c = (PARAMS.view * sphere.xyz().extend(1.0)).xyz();
            let r = sphere.w;
            let hit = sphere_in_frustum(c, r, sides, near, far)
                && sphere_reaches_box(c, r, rays, near, far);
            list_append(hit, start + i, lid);
            i += TILE_THREADS;
        }
    }

    /// The pixel (within the screen) of invocation `lid` of tile `t`.
    fn pixel_of(t: UVec2, lid: u32) -> UVec2 {
        t * tile + UVec2::new(lid % tile, lid / tile)
    }

    #[compute(workgroup_size(tile * tile, 1, 1))]
    pub fn shade(#[builtin(local_invocation_index)] lid: u32, #[builtin(workgroup_id)] wg: UVec3) {
        if lid == 0u32 {
            RANGE_MIN.store(INFINITY_BITS);
            RANGE_MAX.store(0u32);
            EDGE_COUNT.store(0u32);
        }
        workgroup_barrier();
        let pixel = pixel_of(wg.xy(), lid);
        let in_screen = pixel.x < PARAMS.screen.x && pixel.y < PARAMS.screen.y;

        // Depth bounds of every sample, and the edge test against sample 0.
        let mut g0 = load_sample(UVec2::ZERO, 0u32);
        let mut edge = false;
        if in_screen {
            g0 = load_sample(pixel, 0u32);
            let mut dmin = 2.0;
            let mut dmax = -1.0;
            for s in 0u32..msaa {
                let mut g = g0;
                if s > 0u32 {
                    g = load_sample(pixel, s);
                }
                if g.depth < 1.0 {
                    dmin = dmin.min(g.depth);
                    dmax = dmax.max(g.depth);
                }
                if s > 0u32 && differs(pixel, s, g0, g) {
                    edge = true;
                }
            }
            if dmin <= dmax {
                RANGE_MIN.fetch_min(dmin.to_bits());
                RANGE_MAX.fetch_max(dmax.to_bits());
            }
        }
        let mut edge_slot = 0u32;
        if edge {
            if defer {
                edge_slot = EDGE_COUNT.fetch_add(1u32);
                EDGES[edge_slot] = lid;
            }
            if PARAMS.record_edges != 0u32 {
                let bit = pixel.y * PARAMS.screen.x + pixel.x;
                EDGE_BITS[bit / 32u32].fetch_or(1u32 << (bit % 32u32));
            }
        }
        workgroup_barrier();

        // The tile's frustum between its depth bounds.
        let min_bits = RANGE_MIN.load();
        let max_bits = RANGE_MAX.load();
        let opaque = min_bits <= max_bits;
        let near = depth_to_view(f32::from_bits(min_bits));
        let far = depth_to_view(f32::from_bits(max_bits));
        let r = tile_ndc(wg.xy(), tile, PARAMS.screen);
        let sides = side_planes(PARAMS.projection, r);
        let rays = tile_rays(PARAMS.inv_projection, PARAMS.orthographic, r);

        let edges = EDGE_COUNT.load();
        let items = edges * (msaa - 1u32);
        let mut s0 = shading_of(pixel, 0u32, g0);
        if !edge && g0.depth < 1.0 {
            s0 = centre_shading(pixel, g0);
        }
        let mut color = Vec3::ZERO;
        let mut extra = Vec3::ZERO;
        let mut acc = [
            Vec3::ZERO,
            Vec3::ZERO,
            Vec3::ZERO,
            Vec3::ZERO,
            Vec3::ZERO,
            Vec3::ZERO,
            Vec3::ZERO,
        ];
        if in_screen {
            color = unculled(s0);
            if !defer && edge {
                for s in 1u32..msaa {
                    extra += unculled(shading_of(pixel, s, load_sample(pixel, s)));
                }
            }
        }
        if defer {
            for r in 0u32..msaa - 1u32 {
                let item = r * TILE_THREADS + lid;
                if item < items {
                    let p = pixel_of(wg.xy(), EDGES[item % edges]);
                    let s = 1u32 + item / edges;
                    acc[r] = unculled(shading_of(p, s, load_sample(p, s)));
                }
            }
        }

        // The lights, a chunk at a time: cull into LIST, shade, repeat.
        let mut start = 0u32;
        while start < PARAMS.light_count {
            if lid == 0u32 {
                LIST_COUNT.store(0u32);
            }
            workgroup_barrier();
            if opaque {
                let count = (PARAMS.light_count - start).min(CHUNK);
                cull_chunk(start, count, lid, sides, rays, near, far);
            }
            workgroup_barrier();
            let n = LIST_COUNT.load();
            if in_screen {
                color += listed(s0, n);
                if !defer && edge {
                    for s in 1u32..msaa {
                        extra += listed(shading_of(pixel, s, load_sample(pixel, s)), n);
                    }
                }
            }
            if defer {
                for r in 0u32..msaa - 1u32 {
                    let item = r * TILE_THREADS + lid;
                    if item < items {
                        let p = pixel_of(wg.xy(), EDGES[item % edges]);
                        let s = 1u32 + item / edges;
                        acc[r] += listed(shading_of(p, s, load_sample(p, s)), n);
                    }
                }
            }
            workgroup_barrier();
            start += CHUNK;
        }

        // Deferred items back to their pixels, a round at a time.
        if defer {
            for r in 0u32..msaa - 1u32 {
                ITEM_COLOR[lid] = acc[r];
                workgroup_barrier();
                if edge {
                    for s in 1u32..msaa {
                        let item = (s - 1u32) * edges + edge_slot;
                        if item >= r * TILE_THREADS && item < (r + 1u32) * TILE_THREADS {
                            extra += ITEM_COLOR[item - r * TILE_THREADS];
                        }
                    }
                }
                workgroup_barrier();
            }
        }

        if in_screen {
            let mut resolved = color;
            if edge {
                resolved = (color + extra) / msaa as f32;
                if PARAMS.show_frequency != 0u32 {
                    resolved = resolved * 0.25 + Vec3::new(8.0, 0.0, 0.0);
                }
            }
            HDR_OUT.store(pixel, resolved.extend(1.0));
        }
    }

    /// Copies every sample of pixel `gid.xy` to `CAPTURE`: per sample, depth then the albedo,
    /// normal and radiance texels and the view depth (`CAPTURE_WORDS` words), samples of a
    /// pixel together, pixels row-major.
    #[compute(workgroup_size(8, 8, 1))]
    pub fn capture_gbuffer(#[builtin(global_invocation_id)] gid: UVec3) {
        let p = gid.xy();
        if p.x < PARAMS.screen.x && p.y < PARAMS.screen.y {
            for s in 0u32..msaa {
                let g = load_sample(p, s);
                let base = ((p.y * PARAMS.screen.x + p.x) * msaa + s) * CAPTURE_WORDS;
                CAPTURE[base] = g.depth;
                for k in 0u32..4u32 {
                    CAPTURE[base + 1u32 + k] = g.albedo_metallic[k];
                    CAPTURE[base + 5u32 + k] = g.normals[k];
                    CAPTURE[base + 9u32 + k] = g.radiance_roughness[k];
                }
                CAPTURE[base + 13u32] = g.view_depth;
            }
        }
    }
}
