//! The visibility-buffer path's material frame: what a material's visibility kernel does
//! around its `surface` function.

/// The frame of every material's visibility kernel (`vis_shade`, which `#[shader_dsl::material]`
/// adds to a material's variants with `msaa > 0`): one invocation per pixel finds, from the IDs
/// the raster pass left (`vis_raster`), the triangles its samples see, and shades those of its
/// own material program once each, as the forward pass would.
///
/// For a triangle of the pixel (`vis_triangle`, then `vis_point`):
/// 1. **Reconstruction.** Its three vertices (`vis_geometry`) in world space; the point where
///    the view ray through the pixel centre meets the triangle's plane (outside the triangle
///    too, as the forward pass extrapolates its attributes there); its barycentric weights (in
///    world space, so they are the perspective-correct ones) interpolate the normal, tangent,
///    both UV sets and the vertex colour. The screen derivatives (the material's mip choice,
///    the decals' footprint) are differences between the points of the pixel's 2 × 2 quad, in
///    its row and its column, as a fragment shader's fine `dpdx` and `dpdy` take them.
/// 2. **Facing.** A front face is one whose vertices wind counter-clockwise on screen, clockwise
///    for a mirrored draw (`handedness`), as the raster pipelines' `front_face`; a back face of
///    a double-sided material gets the flipped normal.
/// 3. **Material**: the kernel's module's `surface`.
/// 4. **Decals and lights** (`vis_radiance`) through the frame's clustered light lists
///    (`material_frame`'s `shading_point_at` and `lit_radiance` with `list` 2: the point's
///    froxel, shadowed), the very code of the forward pass.
///
/// A pixel whose samples all see one triangle (or the sky) is shaded once; otherwise each
/// distinct triangle once, weighted by the samples it covers (`vis_samples_of`), the sky by
/// the sky's. The material kernel shades the pixels' first distinct IDs in one round, their
/// second ones in the next, and so on, so a subgroup shades as many times as its pixel with
/// the most triangles (a loop over the samples shaded where each ID first appeared, up to a
/// sample count of times). Each test reads the samples' IDs again (from the texture cache): a
/// version that read them once into a local array was 8% slower on the H200 (BENCHMARKS.md).
/// The forward pass shades each triangle at the pixel centre and the resolve averages its
/// samples: the same sum.
///
/// **Several programs.** Each material program's kernel runs over the whole screen and shades
/// only the triangles whose material record names its program (`GpuMaterial::program`,
/// `VIS.program`), adding their coverage-weighted radiance to the pixel's sum in `ACCUM`
/// (`vis_begin` reads what earlier kernels of the frame left). glTF PBR's kernel (program 0)
/// runs last: it adds its triangles and the sky, divides by the sample count and writes
/// `HDR_OUT`. With `show_frequency`, pixels of more than one triangle are drawn red.
#[shader_dsl::library(
    axes(
        list: u32 = [0, 1, 2],
        blend: bool = [false, true],
        scalarize: bool = [false, true],
        msaa: u32 = [0, 1, 2, 4, 8],
        vis64: bool = [false, true],
    ),
    requires(subgroup = scalarize),
    uses(
        crate::forward::material_frame,
        crate::forward::material_surface,
        crate::visibility::samples64::vis64_sample,
        crate::shared::view,
        crate::shared::material_uv,
        crate::shared::material_table,
        crate::shared::pbr,
        crate::shared::light_lists,
        crate::shared::surface_light,
        crate::shared::light_grid,
        crate::shared::shadow_atlas,
        crate::shared::decal_apply,
        crate::shared::octahedral,
        crate::visibility::geometry::vis_geometry,
    ),
)]
pub mod vis_frame {
    /// One kernel's view of the frame beyond the material frame's `Camera` and `Lighting`.
    pub struct VisParams {
        /// World from clip space: the inverse of the camera's view-projection.
        pub world_from_clip: Mat4,
        /// HDR radiance where no surface is.
        pub sky: Vec3,
        /// Draws in `DRAW_GEOMETRY`.
        pub draws: u32,
        pub screen: UVec2,
        /// 1: pixels of more than one triangle are drawn red (the shading-frequency view).
        pub show_frequency: u32,
        /// The material program this kernel shades (`GpuMaterial::program`; 0: glTF PBR, the
        /// last kernel of the frame, which writes `HDR_OUT`).
        pub program: u32,
        /// 1: an earlier kernel of this frame left its sums in `ACCUM`.
        pub accumulated: u32,
        /// The blended draws the forward pass draws over the compute rasteriser's frame
        /// (`vis_blend`'s draw counts).
        pub blended_draws: u32,
        pub pad: UVec2,
    }

    /// A reconstructed point of a triangle seen through a pixel: what `surface` takes, and
    /// where it is on screen with its world-space derivatives.
    pub struct VisPoint {
        pub point: MaterialPoint,
        /// Window position of the pixel centre (pixels).
        pub frag: Vec2,
        /// World position a pixel right and a pixel down, less this one's.
        pub world_dx: Vec3,
        pub world_dy: Vec3,
    }

    #[uniform(group = 0, binding = 15)]
    #[when(msaa > 0)]
    static VIS: VisParams;
    #[texture(group = 0, binding = 16)]
    #[when(msaa == 1 && !vis64)]
    static IDS: Texture2d<u32>;
    #[texture(group = 0, binding = 16)]
    #[when(msaa > 1 && !vis64)]
    static IDS_MS: TextureMultisampled2d<u32>;
    /// With `vis64`: the compute rasteriser's samples (`vis_compute_raster`'s `VIS64`), in
    /// place of the raster targets, as `(low, high)` word pairs, `(y × width + x) × msaa + s`.
    /// A sample holds `(!depth_bits << 32) | !id`, or 0 where no triangle covered it.
    #[storage(group = 0, binding = 16)]
    #[when(msaa > 0 && vis64)]
    static VIS64: [UVec2];
    #[texture(group = 0, binding = 17)]
    #[when(msaa > 0 && !blend)]
    static HDR_OUT: StorageTexture2d<Rgba16Float, Write>;
    /// Per pixel, row by row: the sum of coverage-weighted radiance the kernels so far added.
    #[storage(group = 0, binding = 18, read_write)]
    #[when(msaa > 0 && !blend)]
    static ACCUM: [Vec4];
    /// The raster pass's depth. The ID target is loaded, not cleared (a multisampled clear is
    /// slow on some chips), so a sample no triangle covered holds an old ID: its depth, 1.0,
    /// tells it is sky.
    #[texture(group = 0, binding = 20)]
    #[when(msaa == 1 && !vis64)]
    static VIS_DEPTH: TextureDepth2d;
    #[texture(group = 0, binding = 20)]
    #[when(msaa > 1 && !vis64)]
    static VIS_DEPTH_MS: TextureDepthMultisampled2d;

    // `VIS` exists where `msaa > 0` (the kernels' variants and the blended surfaces drawn over
    // their image), `HDR_OUT` and `ACCUM` only in the kernels' (`!blend`); the
    // library is also checked at `msaa` 0 (a material's forward variants), so what reads them
    // is guarded by the axis.

    /// The screen size in pixels.
    fn vis_screen() -> UVec2 {
        let mut size = UVec2::ZERO;
        if msaa > 0 {
            size = VIS.screen;
        }
        size
    }

    /// World from clip space.
    fn vis_world_from_clip() -> Mat4 {
        let mut m = Mat4::IDENTITY;
        if msaa > 0 {
            m = VIS.world_from_clip;
        }
        m
    }

    /// The draws in `DRAW_GEOMETRY`.
    fn vis_draws() -> u32 {
        let mut n = 0u32;
        if msaa > 0 {
            n = VIS.draws;
        }
        n
    }

    /// Whether pixel `p` is on the screen (the dispatch rounds up to whole workgroups).
    pub fn vis_on_screen(p: UVec2) -> bool {
        let size = vis_screen();
        p.x < size.x && p.y < size.y
    }

    /// The triangle ID of sample `s` of pixel `p` (0: sky, where the depth is 1.0 whatever
    /// the ID target holds; with `vis64`, where no triangle covered the sample).
    pub fn vis_id_at(p: UVec2, s: u32) -> u32 {
        let mut id = 0u32;
        let mut depth = 1.0f32;
        if vis64 {
            if msaa > 0 {
                let sample = VIS64[(p.y * VIS.screen.x + p.x) * msaa + s];
                id = vis64_id(sample);
                depth = vis64_depth(sample);
            }
        } else if msaa == 1 {
            id = IDS.load(p, 0u32).x;
            depth = VIS_DEPTH.load(p, 0u32);
        } else if msaa > 1 {
            id = IDS_MS.load(p, s).x;
            depth = VIS_DEPTH_MS.load(p, s);
        }
        if depth >= 1.0 {
            id = 0u32;
        }
        id
    }

    /// Every sample of a pixel, as a mask (bit `s`: sample `s`).
    pub fn vis_all_samples() -> u32 {
        let mut all = 0u32;
        if msaa > 0 {
            all = (1u32 << msaa) - 1u32;
        }
        all
    }

    /// The samples of `left` (a mask) where pixel `p` sees `id`.
    pub fn vis_samples_of(p: UVec2, id: u32, left: u32) -> u32 {
        let mut seen = 0u32;
        for s in 0u32..msaa {
            if ((left >> s) & 1u32) != 0u32 && vis_id_at(p, s) == id {
                seen = seen | (1u32 << s);
            }
        }
        seen
    }

    /// Scene triangle `id` (not 0, the sky): its draw and vertices.
    pub fn vis_triangle(id: u32) -> SceneTriangle {
        triangle_of(id, vis_draws())
    }

    /// Whether this kernel shades `tri`: its material record names this kernel's program.
    pub fn vis_shades(tri: SceneTriangle) -> bool {
        let mut mine = false;
        if msaa > 0 {
            mine = MATERIALS[DRAWS[tri.draw].material].program == VIS.program;
        }
        mine
    }

    /// The world point where the view ray through window position `at` (pixels) meets the
    /// plane through `a` with normal `n` (the ray's far point when it runs along the plane).
    fn on_plane(at: Vec2, a: Vec3, n: Vec3) -> Vec3 {
        let size = vis_screen().as_vec2();
        let ndc = Vec2::new(2.0 * at.x / size.x - 1.0, 1.0 - 2.0 * at.y / size.y);
        let world_from_clip = vis_world_from_clip();
        let near = world_from_clip * Vec4::new(ndc.x, ndc.y, 0.0, 1.0);
        let far = world_from_clip * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
        let o = near.xyz() / near.w;
        let d = far.xyz() / far.w - o;
        let facing = n.dot(d);
        let mut p = o + d;
        if facing.abs() > 1.0e-12 {
            p = o + d * (n.dot(a - o) / facing);
        }
        p
    }

    /// The barycentric weights of world point `p` in the triangle `a`, `b`, `c`.
    fn weights(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
        let e0 = b - a;
        let e1 = c - a;
        let e2 = p - a;
        let d00 = e0.dot(e0);
        let d01 = e0.dot(e1);
        let d11 = e1.dot(e1);
        let d20 = e2.dot(e0);
        let d21 = e2.dot(e1);
        let denom = d00 * d11 - d01 * d01;
        let mut w = Vec3::new(1.0, 0.0, 0.0);
        if denom.abs() > 0.0 {
            let v = (d11 * d20 - d01 * d21) / denom;
            let u = (d00 * d21 - d01 * d20) / denom;
            w = Vec3::new(1.0 - v - u, v, u);
        }
        w
    }

    fn mix3(w: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
        a * w.x + b * w.y + c * w.z
    }

    fn mix2(w: Vec3, a: Vec2, b: Vec2, c: Vec2) -> Vec2 {
        a * w.x + b * w.y + c * w.z
    }

    fn mix4(w: Vec3, a: Vec4, b: Vec4, c: Vec4) -> Vec4 {
        a * w.x + b * w.y + c * w.z
    }

    /// Triangle `tri` seen through the centre of pixel `p`, rebuilt as the forward pass's
    /// fragment would see it.
    pub fn vis_point(tri: SceneTriangle, p: UVec2) -> VisPoint {
        let draw = DRAWS[tri.draw];
        let v = tri.vertices;
        let w0 = (draw.world_from_mesh * vertex_position(v.x).extend(1.0)).xyz();
        let w1 = (draw.world_from_mesh * vertex_position(v.y).extend(1.0)).xyz();
        let w2 = (draw.world_from_mesh * vertex_position(v.z).extend(1.0)).xyz();
        let plane = (w1 - w0).cross(w2 - w0);
        let frag = p.as_vec2() + Vec2::splat(0.5);
        let world = on_plane(frag, w0, plane);
        // The derivatives a fragment shader's `dpdx` and `dpdy` give (fine: the pixel's row and
        // column of its 2 × 2 quad): differences between the quad's pixels, not this pixel's
        // own neighbours, which a perspective plane makes differ.
        let quad = (p - p % UVec2::splat(2u32)).as_vec2() + Vec2::splat(0.5);
        let left = on_plane(Vec2::new(quad.x, frag.y), w0, plane);
        let right = on_plane(Vec2::new(quad.x + 1.0, frag.y), w0, plane);
        let top = on_plane(Vec2::new(frag.x, quad.y), w0, plane);
        let bottom = on_plane(Vec2::new(frag.x, quad.y + 1.0), w0, plane);
        let bc = weights(world, w0, w1, w2);
        let bl = weights(left, w0, w1, w2);
        let br = weights(right, w0, w1, w2);
        let bt = weights(top, w0, w1, w2);
        let bb = weights(bottom, w0, w1, w2);

        let uv0 = mix2(bc, UV0[v.x], UV0[v.y], UV0[v.z]);
        let uv1 = mix2(bc, UV1[v.x], UV1[v.y], UV1[v.z]);
        let d = UvDerivatives {
            uv0,
            uv1,
            uv0_dx: mix2(br - bl, UV0[v.x], UV0[v.y], UV0[v.z]),
            uv0_dy: mix2(bb - bt, UV0[v.x], UV0[v.y], UV0[v.z]),
            uv1_dx: mix2(br - bl, UV1[v.x], UV1[v.y], UV1[v.z]),
            uv1_dy: mix2(bb - bt, UV1[v.x], UV1[v.y], UV1[v.z]),
        };
        let n = mix3(
            bc,
            vertex_normal(v.x),
            vertex_normal(v.y),
            vertex_normal(v.z),
        );
        let n = (draw.normal_from_mesh * n.extend(0.0)).xyz();
        let t4 = mix4(bc, TANGENTS[v.x], TANGENTS[v.y], TANGENTS[v.z]);
        let t = (draw.world_from_mesh * t4.xyz().extend(0.0)).xyz();
        let color = mix4(bc, COLORS[v.x], COLORS[v.y], COLORS[v.z]);

        // Front: counter-clockwise on screen (the geometric normal towards the eye), clockwise
        // for a mirrored draw.
        let eye = CAMERA.eye_homogeneous;
        let toward_eye = eye.xyz() - world * eye.w;
        let front = (plane.dot(toward_eye) > 0.0) == (draw.handedness > 0.0);
        let nn = select(front, n, -n).normalize();
        let tt = (t - nn * nn.dot(t)).normalize();
        VisPoint {
            point: MaterialPoint {
                world,
                normal: nn,
                tangent: tt,
                bitangent: nn.cross(tt) * (t4.w * draw.handedness),
                uv: d,
                color,
                material: draw.material,
                params: MATERIALS[draw.material].params,
            },
            frag,
            world_dx: right - left,
            world_dy: bottom - top,
        }
    }

    /// The linear HDR radiance of surface `s` at `v`: decals, ambient, emission and the lights
    /// of its froxel, shadowed.
    pub fn vis_radiance(v: VisPoint, s: Surface) -> Vec3 {
        let sp = shading_point_at(v.frag, v.point, s, v.world_dx, v.world_dy);
        lit_radiance(sp, v.frag)
    }

    /// What earlier kernels of the frame added at pixel `p` (nothing for the first).
    pub fn vis_begin(p: UVec2) -> Vec3 {
        let mut sum = Vec3::ZERO;
        if msaa > 0 && !blend {
            if VIS.accumulated != 0u32 {
                sum = ACCUM[p.y * VIS.screen.x + p.x].xyz();
            }
        }
        sum
    }

    /// Leaves pixel `p`'s sum `total` (its samples saw `kinds` distinct IDs) for the next
    /// kernel, or, in glTF PBR's kernel (the last), adds the sky's samples, resolves and writes
    /// `HDR_OUT`.
    pub fn vis_finish(p: UVec2, total: Vec3, kinds: u32) {
        if msaa > 0 && !blend {
            if VIS.program == 0u32 {
                let mut sky = 0u32;
                for s in 0u32..msaa {
                    if vis_id_at(p, s) == 0u32 {
                        sky += 1u32;
                    }
                }
                let mut resolved = (total + VIS.sky * (sky as f32)) / (msaa as f32);
                if VIS.show_frequency != 0u32 && kinds > 1u32 {
                    resolved = Vec3::new(1.0, 0.0, 0.0);
                }
                HDR_OUT.store(p, resolved.extend(1.0));
            } else {
                ACCUM[p.y * VIS.screen.x + p.x] = total.extend(0.0);
            }
        }
    }
}
