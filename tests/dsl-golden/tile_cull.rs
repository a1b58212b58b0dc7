// Golden: the 3-axis tiled light culling kernel (3 × 4 × 2 = 24 variants). Tile size sets the
// workgroup size and workgroup array lengths, MSAA picks the depth texture type and the
// per-sample depth loop, and `scalarize` switches to subgroup reductions and ballot
// compaction (those variants declare the subgroup capability).
#[shader_dsl::shader(
    axes(
        tile: u32 = [8, 16, 32] => "t",
        msaa: u32 = [1, 2, 4, 8],
        scalarize: bool = [false, true] => "scalar",
    ),
    requires(subgroup = scalarize),
)]
pub mod tile_cull {
    pub struct Camera {
        pub view: Mat4,
        pub proj: Mat4,
        pub inv_proj: Mat4,
        pub screen_size: UVec2,
        pub tile_count: UVec2,
        pub light_count: u32,
        pub near: f32,
        pub far: f32,
        pub max_per_tile: u32,
    }

    pub struct Light {
        pub position: Vec3,
        pub radius: f32,
        pub color: Vec3,
        pub kind: u32,
    }

    pub struct TileHeader {
        pub offset: u32,
        pub count: u32,
        pub min_depth: f32,
        pub max_depth: f32,
    }

    const MAX_LIGHTS_PER_TILE: u32 = 256;
    const TILE_PIXELS: u32 = tile * tile;
    const DEPTH_ONE_BITS: u32 = 0x3f80_0000;

    #[uniform(group = 0, binding = 0)]
    static CAMERA: Camera;
    #[storage(group = 0, binding = 1)]
    static LIGHTS: [Light];
    #[storage(group = 0, binding = 2, read_write)]
    static HEADERS: [TileHeader];
    #[storage(group = 0, binding = 3, read_write)]
    static INDICES: [u32];
    #[texture(group = 0, binding = 4)]
    #[when(msaa == 1)]
    static DEPTH: TextureDepth2d;
    #[texture(group = 0, binding = 4)]
    #[when(msaa > 1)]
    static DEPTH_MS: TextureDepthMultisampled2d;

    #[workgroup]
    static TILE_MIN: Atomic<u32>;
    #[workgroup]
    static TILE_MAX: Atomic<u32>;
    #[workgroup]
    static TILE_COUNT: Atomic<u32>;
    #[workgroup]
    static TILE_LIST: [u32; MAX_LIGHTS_PER_TILE];
    #[workgroup]
    static TILE_BASE: u32;

    /// Reads the depth of one pixel: min and max over its samples.
    fn pixel_depth(p: UVec2, dmin: &mut f32, dmax: &mut f32) {
        if msaa == 1 {
            let d = DEPTH.load(p, 0u32);
            *dmin = d;
            *dmax = d;
        } else {
            *dmin = 1.0;
            *dmax = 0.0;
            for s in 0u32..msaa {
                let d = DEPTH_MS.load(p, s);
                *dmin = dmin.min(d);
                *dmax = dmax.max(d);
            }
        }
    }

    /// View-space depth (positive, towards -Z) of a depth-buffer value.
    fn linear_depth(d: f32) -> f32 {
        let near = CAMERA.near;
        let far = CAMERA.far;
        near * far / (far - d * (far - near))
    }

    /// Unprojects a point of the tile rectangle at the far plane into view space.
    fn view_ray(pixel: Vec2) -> Vec3 {
        let size = CAMERA.screen_size.as_vec2();
        let ndc = Vec2::new(pixel.x / size.x * 2.0 - 1.0, 1.0 - pixel.y / size.y * 2.0);
        let p = CAMERA.inv_proj * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
        p.xyz() / p.w
    }

    /// Signed distance from a plane through the origin with the given normal.
    fn plane_distance(normal: Vec3, point: Vec3) -> f32 {
        normal.normalize().dot(point)
    }

    /// Sphere against the tile's side planes and its depth range.
    fn sphere_visible(center: Vec3, radius: f32, corners: &mut Mat4, zmin: f32, zmax: f32) -> bool {
        let c0 = corners.x_axis.xyz();
        let c1 = corners.y_axis.xyz();
        let c2 = corners.z_axis.xyz();
        let c3 = corners.w_axis.xyz();
        let mut inside = true;
        if plane_distance(c0.cross(c1), center) < -radius {
            inside = false;
        }
        if plane_distance(c1.cross(c2), center) < -radius {
            inside = false;
        }
        if plane_distance(c2.cross(c3), center) < -radius {
            inside = false;
        }
        if plane_distance(c3.cross(c0), center) < -radius {
            inside = false;
        }
        let depth = -center.z;
        if depth + radius < zmin || depth - radius > zmax {
            inside = false;
        }
        inside
    }

    /// Appends a light to the tile's shared list (drops it when the list is full).
    fn push_light(index: u32) {
        let slot = TILE_COUNT.fetch_add(1u32);
        if slot < MAX_LIGHTS_PER_TILE {
            TILE_LIST[slot] = index;
        }
    }

    #[compute(workgroup_size(tile, tile, 1))]
    pub fn cull(
        #[builtin(local_invocation_index)] lid: u32,
        #[builtin(workgroup_id)] wg: UVec3,
        #[builtin(global_invocation_id)] gid: UVec3,
    ) {
        if lid == 0u32 {
            TILE_MIN.store(DEPTH_ONE_BITS);
            TILE_MAX.store(0u32);
            TILE_COUNT.store(0u32);
        }
        workgroup_barrier();

        // 1. Depth bounds of the tile.
        let pixel = gid.xy().min(CAMERA.screen_size - UVec2::ONE);
        let mut dmin = 1.0;
        let mut dmax = 0.0;
        pixel_depth(pixel, &mut dmin, &mut dmax);
        if scalarize {
            let wave_min = subgroup_min(dmin);
            let wave_max = subgroup_max(dmax);
            let lane = subgroup_exclusive_add(1u32);
            if subgroup_all(wave_min >= wave_max) || lane == 0u32 {
                TILE_MIN.fetch_min(wave_min.to_bits());
                TILE_MAX.fetch_max(wave_max.to_bits());
            }
        } else {
            TILE_MIN.fetch_min(dmin.to_bits());
            TILE_MAX.fetch_max(dmax.to_bits());
        }
        workgroup_barrier();
        let zmin = linear_depth(TILE_MIN.load().from_bits());
        let zmax = linear_depth(TILE_MAX.load().from_bits());

        // 2. Tile frustum corners (view space, far plane).
        let origin = (wg.xy() * tile).as_vec2();
        let extent = tile as f32;
        let mut corners = Mat4::from_cols(
            view_ray(origin).extend(0.0),
            view_ray(origin + Vec2::new(extent, 0.0)).extend(0.0),
            view_ray(origin + Vec2::splat(extent)).extend(0.0),
            view_ray(origin + Vec2::new(0.0, extent)).extend(0.0),
        );

        // 3. Test lights, TILE_PIXELS at a time.
        let count = CAMERA.light_count;
        let rounds = (count + TILE_PIXELS - 1u32) / TILE_PIXELS;
        for r in 0u32..rounds {
            let index = r * TILE_PIXELS + lid;
            var_guard(index);
            let mut visible = false;
            if index < count {
                let light = LIGHTS[index];
                let center = (CAMERA.view * light.position.extend(1.0)).xyz();
                visible = sphere_visible(center, light.radius, &mut corners, zmin, zmax);
            }
            if scalarize {
                let ballot = subgroup_ballot(visible);
                let total = ballot.x.count_ones() + ballot.y.count_ones() + ballot.z.count_ones() + ballot.w.count_ones();
                let offset = subgroup_exclusive_add(select(visible, 1u32, 0u32));
                let mut base = 0u32;
                if subgroup_any(visible) && subgroup_exclusive_add(1u32) == 0u32 {
                    base = TILE_COUNT.fetch_add(total);
                }
                base = subgroup_broadcast_first(base);
                if visible && base + offset < MAX_LIGHTS_PER_TILE {
                    TILE_LIST[base + offset] = index;
                }
            } else if visible {
                push_light(index);
            }
        }
        workgroup_barrier();

        // 4. Write the tile's header and light list.
        let tile_index = wg.y * CAMERA.tile_count.x + wg.x;
        let stored = TILE_COUNT.load().min(MAX_LIGHTS_PER_TILE).min(CAMERA.max_per_tile);
        let offset = tile_index * CAMERA.max_per_tile;
        if lid == 0u32 {
            TILE_BASE = offset;
            HEADERS[tile_index] = TileHeader { offset, count: stored, min_depth: zmin, max_depth: zmax };
        }
        workgroup_barrier();
        let mut i = lid;
        while i < stored {
            INDICES[TILE_BASE + i] = TILE_LIST[i];
            i += TILE_PIXELS;
        }
    }

    /// Keeps the light index in range for the bounds-checked storage reads.
    fn var_guard(index: u32) {
        let _ = index.min(MAX_LIGHTS_PER_TILE * 1024u32);
    }
}
