//! The frame every material is shaded in: what a material's surface function is given and what
//! it returns, and everything around it (vertex stage, alpha mask, decals, the light loops over
//! the naive, tiled or clustered lists, the G-buffer), so that a material is one function.

/// What a material's `surface` function is given (`MaterialPoint`) and returns (`Surface`),
/// and `tangent_space_normal` for normal maps: the types a library of surfaces needs, without
/// the frame's axes and bindings.
#[shader_dsl::library(uses(crate::shared::material_uv, crate::shared::material_table))]
pub mod material_surface {
    /// A point of a surface as a material's `surface` function gets it.
    pub struct MaterialPoint {
        /// World-space position.
        pub world: Vec3,
        /// Unit normal of the geometry, towards the viewer's side (flipped on back faces).
        pub normal: Vec3,
        /// Unit tangent (orthogonal to `normal`) and bitangent: the tangent frame of normal
        /// maps (`tangent_space_normal`).
        pub tangent: Vec3,
        pub bitangent: Vec3,
        /// Both UV sets and their screen derivatives, for `material_texel` and `atlas_sample`.
        pub uv: UvDerivatives,
        /// `COLOR_0`, linear RGBA (white where the primitive has none).
        pub color: Vec4,
        /// The material's record (`MATERIALS` index): its glTF factors and textures.
        pub material: u32,
        /// Where the material's parameters are in its own `PARAMS` (the record's `params`).
        pub params: u32,
    }

    /// What a material's `surface` function returns: the inputs of lighting.
    pub struct Surface {
        /// Linear base colour (`rgb`) and coverage (`a`: the blended variants' output alpha).
        pub base_color: Vec4,
        /// Unit shading normal, world space (`tangent_space_normal` for a normal map).
        pub normal: Vec3,
        pub metallic: f32,
        pub roughness: f32,
        /// Ambient occlusion, 1 for none (scales the ambient term only).
        pub occlusion: f32,
        /// Emitted radiance.
        pub emissive: Vec3,
    }

    /// The world-space unit normal of a tangent-space normal `ts` (a normal map's texel,
    /// `2 × rgb − 1`, its `xy` scaled as the material likes) at `point`.
    pub fn tangent_space_normal(point: MaterialPoint, ts: Vec3) -> Vec3 {
        (point.tangent * ts.x + point.bitangent * ts.y + point.normal * ts.z).normalize()
    }
}

/// The material frame: the forward and G-buffer programs of every material, less the material.
///
/// A material is a module written with `#[shader_dsl::material]`, which uses this library and
/// adds the entry points (`vs_forward`, `fs_forward`, `fs_gbuffer`) around the module's
/// `surface` function: `surface(point: MaterialPoint) -> Surface`, or, for a material with a
/// parameter struct `P`, `surface(point: MaterialPoint, params: P) -> Surface`. glTF
/// metallic-roughness (`forward`, with `gltf_material`) is one such material.
///
/// Shading, per fragment:
/// 1. `material_vertex`: the draw's record (`DRAWS`, found by instance index) places the vertex.
/// 2. `material_point`: the point's frame (facing, unit normal, tangent and bitangent, both UV
///    sets with their screen derivatives, vertex colour). An alpha-masked material's fragments
///    whose alpha (the material record's base colour factor × base colour texture × vertex
///    alpha) is below its cutoff are discarded here, by the very test the masked pre-Z and
///    shadow casters run (`material_table`'s `masked_out`), so depth and colour agree for every
///    material.
/// 3. The material's `surface`.
/// 4. `material_forward`: decals (`decal_apply`, in layer order: every decal on the naive path,
///    the cell's decal list on the culled paths), ambient, and every light of the fragment's
///    list, shadowed (`surface_light`'s `light_contribution`); or `material_gbuffer`: decals,
///    then the G-buffer of the deferred paths.
///
/// `list` picks how the punctual light list of a fragment is found:
/// * `0` naive: every light `LIGHTS[0..light_count]`;
/// * `1` tiled: `GRID[ty * tiles.x + tx]` with `(tx, ty) = floor(frag_coord.xy / tile_size)`;
///   blended draws (`blend`) read the transparent list, `blend_cell_offset` entries further;
/// * `2` clustered: `GRID[k * tiles.x * tiles.y + ty * tiles.x + tx]` with `k` the depth slice
///   of the fragment's view depth by `light_grid`'s `slice_of`.
///
/// `GRID` entries are `(offset, count)` into `INDICES`, which index `LIGHTS`, as the culling
/// kernels write them. Directional lights are never culled: the first `directional_count` of
/// `DIRECTIONAL` shade every fragment.
///
/// With `blend` the output alpha is the surface's (alpha blend); otherwise 1. The `blend`
/// variant is drawn with no face culled: it takes the front face from `front_facing` and the
/// draw's handedness and discards back faces of single-sided materials (`forward_facing`).
///
/// With `scalarize` (tiled and clustered only), when every lane of the subgroup shares one list
/// the list is read through `subgroup_broadcast_first` (uniform loads and loop, as in DOOM
/// 2016); otherwise each lane walks its own list.
#[shader_dsl::library(
    axes(
        list: u32 = [0, 1, 2],
        blend: bool = [false, true],
        scalarize: bool = [false, true],
    ),
    requires(subgroup = scalarize),
    uses(
        crate::forward::material_surface,
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
pub mod material_frame {
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

    #[uniform(group = 0, binding = 0)]
    static CAMERA: Camera;
    #[uniform(group = 0, binding = 5)]
    static LIGHTING: Lighting;

    /// The vertex stage of every material: the draw's record (`DRAWS[draw_index]`) places the
    /// vertex and names the material.
    pub fn material_vertex(
        position: Vec3,
        normal: Vec3,
        uv: Vec2,
        tangent: Vec4,
        uv1: Vec2,
        color: Vec4,
        draw_index: u32,
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

    /// Whether the fragment is lit as a front face. Blended draws share one pipeline that culls
    /// no face (so one multi-draw takes them all, sorted back to front whatever their
    /// sidedness): there the front comes from the draw's handedness, and a single-sided
    /// material's back faces are discarded, before any texture read or light (WGSL's discard
    /// demotes the invocation to a helper, so the derivatives taken after stay defined).
    pub fn forward_facing(input: VsOut, front: bool) -> bool {
        let mut facing = front;
        if blend {
            facing = front == (input.handedness > 0.0);
            if !facing && MATERIALS[input.material].double_sided == 0u32 {
                discard();
            }
        }
        facing
    }

    /// The point a material shades (fragment shaders, uniform control flow: the UV derivatives
    /// are taken here), after the alpha mask's discard. Back faces (double-sided materials)
    /// get the flipped normal (glTF 2.0).
    pub fn material_point(input: VsOut, front: bool) -> MaterialPoint {
        let d = fragment_derivatives(input);
        material_point_from(input, front, d)
    }

    /// The screen derivatives a fragment's shading takes: both UV sets' and the world
    /// position's.
    pub struct FragmentDerivatives {
        pub uv: UvDerivatives,
        pub p_dx: Vec3,
        pub p_dy: Vec3,
    }

    /// `input`'s screen derivatives (uniform control flow). A fragment that may be discarded
    /// before it shades takes them first: naga writes `discard` as `OpKill`, which ends the
    /// invocation, and the rest of its 2 × 2 quad would read undefined derivatives after.
    pub fn fragment_derivatives(input: VsOut) -> FragmentDerivatives {
        FragmentDerivatives {
            uv: uv_derivatives(input.uv, input.uv1),
            p_dx: dpdx(input.world),
            p_dy: dpdy(input.world),
        }
    }

    /// [`material_point`] with the derivatives `derivatives` taken before.
    pub fn material_point_from(
        input: VsOut,
        front: bool,
        derivatives: FragmentDerivatives,
    ) -> MaterialPoint {
        let d = derivatives.uv;
        if masked_out(input.material, d, input.color.w) {
            discard();
        }
        // Tangent frame (Gram-Schmidt), bitangent handedness in tangent.w.
        let nn = select(front, input.normal, -input.normal).normalize();
        let t = (input.tangent.xyz() - nn * nn.dot(input.tangent.xyz())).normalize();
        MaterialPoint {
            world: input.world,
            normal: nn,
            tangent: t,
            bitangent: nn.cross(t) * input.tangent.w,
            uv: d,
            color: input.color,
            material: input.material,
            params: MATERIALS[input.material].params,
        }
    }

    /// The `GRID` cell of the point at window position `frag` (pixels) and `view_depth`: its
    /// tile's list (opaque or transparent), or its froxel (by `light_grid`, like the culling
    /// kernels).
    fn cell_of(frag: Vec2, view_depth: f32) -> u32 {
        let px = frag.floor().as_uvec2();
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

    /// A surface with its decals applied, where it is: what both the lit output and the
    /// G-buffer take.
    pub struct ShadingPoint {
        p: Vec3,
        view_depth: f32,
        /// Unit normal of the geometry, flipped for back faces.
        geometric_normal: Vec3,
        /// The fragment's `GRID` cell (0 on the naive path).
        cell: u32,
        /// The surface's coverage (blended materials' alpha).
        alpha: f32,
        m: DecalSurface,
    }

    fn shading_point(input: VsOut, point: MaterialPoint, s: Surface) -> ShadingPoint {
        let p = point.world;
        shading_point_at(input.clip.xy(), point, s, dpdx(p), dpdy(p))
    }

    /// [`shading_point`] of a point at window position `frag` (pixels) whose world position
    /// changes by `p_dx` and `p_dy` a pixel right and down: for compute shaders, which find
    /// those derivatives themselves.
    pub fn shading_point_at(
        frag: Vec2,
        point: MaterialPoint,
        s: Surface,
        p_dx: Vec3,
        p_dy: Vec3,
    ) -> ShadingPoint {
        let p = point.world;
        let view_depth = -(CAMERA.view * p.extend(1.0)).z;
        let frame = DecalFrame {
            position: p,
            dpdx: p_dx,
            dpdy: p_dy,
            geometric_normal: point.normal,
            distance: (CAMERA.eye - p).length(),
        };
        let material = DecalSurface {
            albedo: s.base_color.xyz(),
            normal: s.normal,
            occlusion: s.occlusion,
            roughness: s.roughness,
            metallic: s.metallic,
            emissive: s.emissive,
        };
        let mut cell = 0u32;
        if list > 0 {
            cell = cell_of(frag, view_depth);
        }
        ShadingPoint {
            p,
            view_depth,
            geometric_normal: point.normal,
            cell,
            alpha: s.base_color.w,
            m: with_decals(material, frame, cell),
        }
    }

    /// The frame's hemisphere ambient radiance at shading normal `n`.
    fn ambient(n: Vec3) -> Vec3 {
        hemisphere_ambient(LIGHTING.ambient_sky, LIGHTING.ambient_ground, n)
    }

    /// The G-buffer of surface `s` at `point`, decals applied.
    pub fn material_gbuffer(input: VsOut, point: MaterialPoint, s: Surface) -> GBufferOut {
        let sp = shading_point(input, point, s);
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

    /// The lit colour of surface `s` at `point` (linear HDR; alpha 1, or the surface's
    /// coverage on the blended variants), decals applied.
    pub fn material_forward(input: VsOut, point: MaterialPoint, s: Surface) -> Vec4 {
        let p = point.world;
        let d = FragmentDerivatives {
            uv: point.uv,
            p_dx: dpdx(p),
            p_dy: dpdy(p),
        };
        material_forward_from(input, point, s, d)
    }

    /// [`material_forward`] with the derivatives `d` taken before.
    pub fn material_forward_from(
        input: VsOut,
        point: MaterialPoint,
        s: Surface,
        d: FragmentDerivatives,
    ) -> Vec4 {
        let sp = shading_point_at(input.clip.xy(), point, s, d.p_dx, d.p_dy);
        let mut alpha = 1.0;
        if blend {
            alpha = sp.alpha;
        }
        lit_radiance(sp, input.clip.xy()).extend(alpha)
    }

    /// The linear HDR radiance of `sp` seen at window position `frag` (pixels): ambient,
    /// emission and every light of the point's list, shadowed.
    pub fn lit_radiance(sp: ShadingPoint, frag: Vec2) -> Vec3 {
        let m = sp.m;
        let p = sp.p;
        let cell = sp.cell;
        let eye = CAMERA.eye_homogeneous;
        let v = (eye.xyz() - p * eye.w).normalize();
        let lit = LitPoint {
            p,
            n: m.normal,
            v,
            albedo: m.albedo,
            metallic: m.metallic.saturate(),
            roughness: m.roughness.clamp(MIN_ROUGHNESS, 1.0),
            geometric_normal: sp.geometric_normal,
            view_depth: sp.view_depth,
            dither: dither_noise(frag),
        };

        let mut color = ambient(m.normal) * m.albedo * m.occlusion + m.emissive;
        for i in 0u32..LIGHTING.directional_count {
            color += light_contribution(DIRECTIONAL[i], lit);
        }
        if list == 0 {
            for i in 0u32..LIGHTING.light_count {
                color += light_contribution(LIGHTS[i], lit);
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
                        color += light_contribution(LIGHTS[index], lit);
                    }
                    done = true;
                }
            }
            if !done {
                let range = GRID[cell];
                for j in 0u32..range.y {
                    let index = INDICES[range.x + j];
                    color += light_contribution(LIGHTS[index], lit);
                }
            }
        }
        color
    }
}
