//! Forward shading: PBR metallic-roughness over the naive, tiled or clustered light lists.

/// Forward+ / clustered forward shading (the `pbr` library's `shade_light`: GGX distribution,
/// Smith/Schlick-GGX geometry, Schlick Fresnel, Lambert diffuse) into an `Rgba16Float` linear
/// HDR target at location 0. `Camera` and the draw records `DRAWS` come from the `view` library (shared with
/// `prez`), and so does the clip position; the cell lookups are the `light_grid` library's.
///
/// `list` picks how the punctual light list of a fragment is found:
/// * `0` naive: every light `LIGHTS[0..light_count]`;
/// * `1` tiled: `GRID[ty * tiles.x + tx]` with `(tx, ty) = floor(frag_coord.xy / tile_size)`;
///   blended draws (`blend`) read the transparent list, `blend_cell_offset` entries further;
/// * `2` clustered: `GRID[k * tiles.x * tiles.y + ty * tiles.x + tx]` with `k` the depth slice
///   of the fragment's view depth by `light_grid`'s `slice_of`.
///
/// `GRID` entries are `(offset, count)` into `INDICES`, which index `LIGHTS`, as the culling
/// kernels write them. Directional lights are never culled: they live in their own storage
/// array `DIRECTIONAL` and the first `directional_count` of them shade every fragment. `LIGHTS`
/// holds the punctual (point and spot) lights, in the culling pass's item order.
///
/// Falloff and spot cone: see the `pbr` library. Every light with a shadow (`GpuLight::shadow`)
/// is attenuated by the `shadow_atlas` library's `shadow_visibility`, the one PCF path of every
/// light type, on every list and blend variant alike.
///
/// Decals (`decal_apply`) are blended into the material before lighting, in layer order: on the
/// naive path every decal `DECALS[0..decal_count]`, on the culled paths the cell's decal list
/// (grid entry `cell + decal_section`, ascending decal indices). Derivatives of the world
/// position are taken once, before any list loop, so decals filter right in any control flow.
///
/// With `blend` the output alpha is the material's (alpha blend); otherwise 1. The `blend`
/// variant is drawn with no face culled: it takes the front face from `front_facing` and the
/// draw's handedness and discards back faces of single-sided materials. Alpha mask: a
/// material with a positive `alpha_cutoff` discards texels below it.
///
/// The vertex colour (`COLOR_0`) multiplies the base colour, alpha included. Each of the five
/// textures is read through its own UV set and `KHR_texture_transform` from the material atlas,
/// with its glTF sampler's wrap and filters (`material_table`'s `material_texel`): the draw's
/// record names its material in `MATERIALS`, so every draw shares group 2.
///
/// With `scalarize` (tiled and clustered only), when every lane of the subgroup shares one list
/// the list is read through `subgroup_broadcast_first` (uniform loads and loop, as in DOOM
/// 2016); otherwise each lane walks its own list.
#[shader_dsl::shader(
    axes(
        list: u32 = [0, 1, 2] => "list",
        blend: bool = [false, true] => "blend",
        scalarize: bool = [false, true] => "scalar",
    ),
    exclude(list == 0 && scalarize),
    requires(subgroup = scalarize),
    uses(
        crate::shared::view,
        crate::shared::pbr,
        crate::shared::light_lists,
        crate::shared::surface_light,
        crate::shared::light_grid,
        crate::shared::shadow_atlas,
        crate::shared::decal_apply,
        crate::shared::octahedral,
        crate::shared::material_uv,
        crate::shared::material_table,
    ),
)]
pub mod forward {
    /// Light counts and the light-grid geometry of the frame.
    pub struct Lighting {
        /// Ambient radiance from straight up, world +Y (times base colour and occlusion; the
        /// `pbr` library's `hemisphere_ambient` blends it with `ambient_ground` by the shading
        /// normal).
        pub ambient_sky: Vec3,
        /// Punctual lights in `LIGHTS` (naive loop bound).
        pub light_count: u32,
        /// Ambient radiance from straight down, world −Y.
        pub ambient_ground: Vec3,
        /// Tiles across and down (tiled and clustered).
        pub tiles: UVec2,
        /// Tile size in pixels (tiled and clustered).
        pub tile_size: u32,
        /// Depth slices (clustered).
        pub slices: u32,
        /// Grid entries from a tile's opaque list to its transparent list (tiled; 0 when the
        /// culling pass writes none).
        pub blend_cell_offset: u32,
        /// View depth where slice 1 starts (clustered).
        pub near: f32,
        /// View depth where the last slice starts (clustered).
        pub far: f32,
        /// Directional lights at the start of `DIRECTIONAL`.
        pub directional_count: u32,
        /// Decals in `DECALS` (naive loop bound).
        pub decal_count: u32,
        /// Grid entries from a cell's light list to its decal list (the culling pass's grid
        /// section).
        pub decal_section: u32,
    }

    pub struct VsOut {
        #[builtin(position)]
        #[invariant]
        pub clip: Vec4,
        #[location(0)]
        pub world: Vec3,
        #[location(1)]
        pub normal: Vec3,
        #[location(2)]
        pub uv: Vec2,
        #[location(3)]
        pub tangent: Vec4,
        /// `TEXCOORD_1` (the renderer binds `TEXCOORD_0`'s data where a primitive has none).
        #[location(4)]
        pub uv1: Vec2,
        /// `COLOR_0`, linear RGBA (white where a primitive has none).
        #[location(5)]
        pub color: Vec4,
        /// The draw's material (`MATERIALS` index).
        #[location(6)]
        #[interpolate(flat)]
        pub material: u32,
        /// The draw's `handedness` (-1: mirrored, its front faces wind clockwise), for the
        /// blended pipeline, which culls no face and finds the front itself.
        #[location(7)]
        #[interpolate(flat)]
        pub handedness: f32,
    }

    #[uniform(group = 0, binding = 0)]
    static CAMERA: Camera;
    #[uniform(group = 0, binding = 5)]
    static LIGHTING: Lighting;

    #[vertex]
    pub fn vs_forward(
        #[location(0)] position: Vec3,
        #[location(1)] normal: Vec3,
        #[location(2)] uv: Vec2,
        #[location(3)] tangent: Vec4,
        #[location(4)] uv1: Vec2,
        #[location(5)] color: Vec4,
        #[builtin(instance_index)] draw_index: u32,
    ) -> VsOut {
        let draw = DRAWS[draw_index];
        let world = draw.world_from_mesh * position.extend(1.0);
        let n = (draw.normal_from_mesh * normal.extend(0.0)).xyz();
        let t = (draw.world_from_mesh * tangent.xyz().extend(0.0)).xyz();
        VsOut {
            clip: clip_position(CAMERA.view_projection, draw.world_from_mesh, position),
            world: world.xyz(),
            normal: n,
            uv,
            tangent: t.extend(tangent.w * draw.handedness),
            uv1,
            color,
            material: draw.material,
            handedness: draw.handedness,
        }
    }

    /// The `GRID` cell of a fragment: its tile's list (opaque or transparent), or its froxel (by `light_grid`, like the
    /// culling kernels).
    fn cell_of(frag: Vec4, view_depth: f32) -> u32 {
        let px = frag.xy().floor().as_uvec2();
        let mut cell = 0u32;
        if list == 1 {
            cell = tile_cell(px, LIGHTING.tile_size, LIGHTING.tiles.x);
            if blend {
                cell += LIGHTING.blend_cell_offset;
            }
        } else {
            let slice = slice_of(view_depth, LIGHTING.near, LIGHTING.far, LIGHTING.slices);
            cell = froxel_cell(px, slice, LIGHTING.tile_size, LIGHTING.tiles);
        }
        cell
    }

    /// `material` with the decals that reach the shaded point applied, in layer order: every
    /// decal on the naive path, the decal list of `cell` on the culled paths.
    fn with_decals(material: DecalSurface, frame: DecalFrame, cell: u32) -> DecalSurface {
        let mut m = material;
        if list == 0 {
            for d in 0u32..LIGHTING.decal_count {
                m = apply_decal(d, m, frame);
            }
        } else {
            let range = GRID[cell + LIGHTING.decal_section];
            for j in 0u32..range.y {
                m = apply_decal(INDICES[range.x + j], m, frame);
            }
        }
        m
    }

    /// The fragment's material with its decals applied, where it is: what both the lit output
    /// and the G-buffer take. Alpha-masked texels below the cutoff are discarded here.
    struct ShadingPoint {
        p: Vec3,
        view_depth: f32,
        /// Unit normal of the geometry, flipped for back faces.
        geometric_normal: Vec3,
        /// The fragment's `GRID` cell (0 on the naive path).
        cell: u32,
        /// Base-colour alpha (blended materials' coverage).
        alpha: f32,
        m: DecalSurface,
    }

    fn shading_point(input: VsOut, front: bool) -> ShadingPoint {
        let m = MATERIALS[input.material];
        let d = uv_derivatives(input.uv, input.uv1);
        let base = m.base_color
            * material_texel(m.base_color_texture, true, m.base_color_uv, d, Vec4::ONE)
            * input.color;
        // Alpha mask: a positive cutoff marks a masked material (0 for opaque and blend).
        if m.alpha_cutoff > 0.0 && base.w < m.alpha_cutoff {
            discard();
        }
        let mr = material_texel(
            m.metallic_roughness_texture,
            false,
            m.metallic_roughness_uv,
            d,
            Vec4::ONE,
        );
        let occlusion_texel =
            material_texel(m.occlusion_texture, false, m.occlusion_uv, d, Vec4::ONE).x;
        let emissive = m.emissive
            * material_texel(m.emissive_texture, true, m.emissive_uv, d, Vec4::ONE).xyz();
        let flat = Vec4::new(0.5, 0.5, 1.0, 1.0);
        let tangent_normal =
            material_texel(m.normal_texture, false, m.normal_uv, d, flat).xyz() * 2.0 - 1.0;

        // Tangent frame (Gram-Schmidt), bitangent handedness in tangent.w.
        // Back faces (double-sided materials) are lit with the flipped normal (glTF 2.0).
        let nn = select(front, input.normal, -input.normal).normalize();
        let t = (input.tangent.xyz() - nn * nn.dot(input.tangent.xyz())).normalize();
        let b = nn.cross(t) * input.tangent.w;
        let ts = Vec3::new(
            tangent_normal.x * m.normal_scale,
            tangent_normal.y * m.normal_scale,
            tangent_normal.z,
        );
        let n = (t * ts.x + b * ts.y + nn * ts.z).normalize();

        let p = input.world;
        let view_depth = -(CAMERA.view * p.extend(1.0)).z;
        let frame = DecalFrame {
            position: p,
            dpdx: dpdx(p),
            dpdy: dpdy(p),
            geometric_normal: nn,
            distance: (CAMERA.eye - p).length(),
        };
        let material = DecalSurface {
            albedo: base.xyz(),
            normal: n,
            occlusion: 1.0 + m.occlusion_strength * (occlusion_texel - 1.0),
            roughness: m.roughness * mr.y,
            metallic: m.metallic * mr.z,
            emissive,
        };
        let mut cell = 0u32;
        if list > 0 {
            cell = cell_of(input.clip, view_depth);
        }
        ShadingPoint {
            p,
            view_depth,
            geometric_normal: nn,
            cell,
            alpha: base.w,
            m: with_decals(material, frame, cell),
        }
    }

    /// The frame's hemisphere ambient radiance at shading normal `n`.
    fn ambient(n: Vec3) -> Vec3 {
        hemisphere_ambient(LIGHTING.ambient_sky, LIGHTING.ambient_ground, n)
    }

    /// The G-buffer of tile-based deferred shading (`tbdr`) and traditional deferred shading,
    /// one sample's worth (MSAA: the fragment's value goes to every sample it covers):
    /// * location 0, `Rgba8UnormSrgb`: albedo after decals (`rgb`), metalness (`a`);
    /// * location 1, `Rgba16Float`: the octahedral shading normal (`xy`) and geometric normal
    ///   (`zw`, the shadow lookup's normal offset);
    /// * location 2, `Rgba16Float`: the base radiance, hemisphere ambient (at the shading
    ///   normal) × albedo × occlusion + emissive
    ///   (`rgb`; occlusion scales only the ambient term, so it is folded in here), and the
    ///   clamped roughness (`a`);
    /// * location 3, `R32Float`: the view depth, where deferred shading puts the shaded point
    ///   (the pre-Z depth loses millimetres with a glTF camera's tiny near plane).
    ///
    /// 24 bytes per sample plus the pre-Z depth; every value is the very one the forward
    /// fragment lights.
    pub struct GBufferOut {
        #[location(0)]
        pub albedo_metallic: Vec4,
        #[location(1)]
        pub normals: Vec4,
        #[location(2)]
        pub radiance_roughness: Vec4,
        #[location(3)]
        pub view_depth: f32,
    }

    #[fragment]
    pub fn fs_gbuffer(input: VsOut, #[builtin(front_facing)] front: bool) -> GBufferOut {
        let sp = shading_point(input, front);
        let m = sp.m;
        let n = octahedral_encode(m.normal);
        let g = octahedral_encode(sp.geometric_normal);
        GBufferOut {
            albedo_metallic: m.albedo.extend(m.metallic.saturate()),
            normals: Vec4::new(n.x, n.y, g.x, g.y),
            radiance_roughness: (ambient(m.normal) * m.albedo * m.occlusion + m.emissive)
                .extend(m.roughness.clamp(MIN_ROUGHNESS, 1.0)),
            view_depth: sp.view_depth,
        }
    }

    #[fragment]
    pub fn fs_forward(input: VsOut, #[builtin(front_facing)] front: bool) -> Vec4 {
        // Blended draws share one pipeline that culls no face (so one multi-draw takes them
        // all, sorted back to front whatever their sidedness): the fragment finds its front
        // from the draw's handedness and drops a single-sided material's back faces.
        let mut facing = front;
        if blend {
            facing = front == (input.handedness > 0.0);
            // Before any texture read or light: WGSL's discard demotes the invocation to a
            // helper, so the derivatives `shading_point` takes stay defined.
            if !facing && MATERIALS[input.material].double_sided == 0u32 {
                discard();
            }
        }
        let sp = shading_point(input, facing);
        let m = sp.m;
        let p = sp.p;
        let nn = sp.geometric_normal;
        let view_depth = sp.view_depth;
        let cell = sp.cell;

        let albedo = m.albedo;
        let occlusion = m.occlusion;
        let eye = CAMERA.eye_homogeneous;
        let v = (eye.xyz() - p * eye.w).normalize();
        let s = LitPoint {
            p,
            n: m.normal,
            v,
            albedo,
            metallic: m.metallic.saturate(),
            roughness: m.roughness.clamp(MIN_ROUGHNESS, 1.0),
            geometric_normal: nn,
            view_depth,
            dither: dither_noise(input.clip.xy()),
        };

        let mut color = ambient(m.normal) * albedo * occlusion + m.emissive;
        for i in 0u32..LIGHTING.directional_count {
            color += light_contribution(DIRECTIONAL[i], s);
        }
        if list == 0 {
            for i in 0u32..LIGHTING.light_count {
                color += light_contribution(LIGHTS[i], s);
            }
        } else {
            let mut done = false;
            if scalarize {
                let first = subgroup_broadcast_first(cell);
                if subgroup_all(first == cell) {
                    // One list for the whole subgroup: uniform loads and trip count.
                    let range = subgroup_broadcast_first(GRID[first]);
                    for j in 0u32..range.y {
                        let index = subgroup_broadcast_first(INDICES[range.x + j]);
                        color += light_contribution(LIGHTS[index], s);
                    }
                    done = true;
                }
            }
            if !done {
                let range = GRID[cell];
                for j in 0u32..range.y {
                    let index = INDICES[range.x + j];
                    color += light_contribution(LIGHTS[index], s);
                }
            }
        }
        let mut alpha = 1.0;
        if blend {
            alpha = sp.alpha;
        }
        color.extend(alpha)
    }
}
