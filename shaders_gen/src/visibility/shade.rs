//! Materials and lighting of the visibility-buffer path, in compute.

/// Visibility-buffer shading: one invocation per pixel finds, from the IDs the raster pass left
/// (`vis_raster`), the triangles its samples see, and shades each of them once, as the forward
/// pass would, then writes the resolved HDR colour.
///
/// For a triangle of the pixel:
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
/// 3. **Material**: glTF metallic-roughness (`gltf_material`'s `gltf_surface`).
/// 4. **Decals and lights** through the frame's clustered light lists (`material_frame`'s
///    `shading_point_at` and `lit_radiance` with `list` 2: the point's froxel, shadowed), the
///    very code of the forward pass.
///
/// A pixel whose samples all see one triangle (or the sky) is shaded once; otherwise each
/// distinct triangle once, weighted by the samples it covers, the sky by the sky's. The
/// forward pass shades each triangle at the pixel centre and the resolve averages its samples:
/// the same sum. With `show_frequency`, pixels of more than one triangle are drawn red.
#[shader_dsl::shader(
    axes(
        list: u32 = [2],
        blend: bool = [false],
        scalarize: bool = [false, true] => "scalar",
        msaa: u32 = [1, 2, 4, 8],
    ),
    requires(subgroup = scalarize),
    uses(
        crate::forward::material_frame,
        crate::forward::material_surface,
        crate::forward::gltf_material,
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
pub mod vis_shade {
    /// The frame as the kernel needs it beyond the material frame's `Camera` and `Lighting`.
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
    }

    #[uniform(group = 0, binding = 15)]
    static VIS: VisParams;
    #[texture(group = 0, binding = 16)]
    #[when(msaa == 1)]
    static IDS: Texture2d<u32>;
    #[texture(group = 0, binding = 16)]
    #[when(msaa > 1)]
    static IDS_MS: TextureMultisampled2d<u32>;
    #[texture(group = 0, binding = 17)]
    static HDR_OUT: StorageTexture2d<Rgba16Float, Write>;

    /// The triangle ID of sample `s` of pixel `p` (0: sky).
    fn id_at(p: UVec2, s: u32) -> u32 {
        let mut id = 0u32;
        if msaa == 1 {
            id = IDS.load(p, 0u32).x;
        } else {
            id = IDS_MS.load(p, s).x;
        }
        id
    }

    /// The world point where the view ray through window position `at` (pixels) meets the
    /// plane through `a` with normal `n` (the ray's far point when it runs along the plane).
    fn on_plane(at: Vec2, a: Vec3, n: Vec3) -> Vec3 {
        let size = VIS.screen.as_vec2();
        let ndc = Vec2::new(2.0 * at.x / size.x - 1.0, 1.0 - 2.0 * at.y / size.y);
        let near = VIS.world_from_clip * Vec4::new(ndc.x, ndc.y, 0.0, 1.0);
        let far = VIS.world_from_clip * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
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

    /// The linear HDR radiance of triangle `id` seen through the centre of pixel `p`.
    fn shade_triangle(id: u32, p: UVec2) -> Vec3 {
        let tri = triangle_of(id, VIS.draws);
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
        let world_dx = right - left;
        let world_dy = bottom - top;

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
        let point = MaterialPoint {
            world,
            normal: nn,
            tangent: tt,
            bitangent: nn.cross(tt) * (t4.w * draw.handedness),
            uv: d,
            color,
            material: draw.material,
            params: MATERIALS[draw.material].params,
        };
        let s = gltf_surface(point);
        let sp = shading_point_at(frag, point, s, world_dx, world_dy);
        lit_radiance(sp, frag)
    }

    /// Shades pixel `gid.xy` (8 × 8 pixels a workgroup): each distinct triangle of its samples
    /// once.
    #[compute(workgroup_size(8, 8, 1))]
    pub fn shade(#[builtin(global_invocation_id)] gid: UVec3) {
        let p = gid.xy();
        if p.x < VIS.screen.x && p.y < VIS.screen.y {
            shade_pixel(p);
        }
    }

    fn shade_pixel(p: UVec2) {
        let mut total = Vec3::ZERO;
        let mut kinds = 0u32;
        for s in 0u32..msaa {
            let id = id_at(p, s);
            let mut first = true;
            for r in 0u32..s {
                if id_at(p, r) == id {
                    first = false;
                }
            }
            if first {
                kinds += 1u32;
                let mut count = 0u32;
                for r in s..msaa {
                    if id_at(p, r) == id {
                        count += 1u32;
                    }
                }
                let mut color = VIS.sky;
                if id != 0u32 {
                    color = shade_triangle(id, p);
                }
                total += color * (count as f32);
            }
        }
        let mut resolved = total / (msaa as f32);
        if VIS.show_frequency != 0u32 && kinds > 1u32 {
            resolved = Vec3::new(1.0, 0.0, 0.0);
        }
        HDR_OUT.store(p, resolved.extend(1.0));
    }
}
