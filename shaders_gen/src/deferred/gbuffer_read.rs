//! Reading the tile-based deferred path's MSAA G-buffer: the `tbdr_gbuffer` library, which the
//! `tbdr` kernel and its light-volume entry points use.

/// The G-buffer as the deferred shading entry points read it: the frame's parameters
/// (`TbdrParams`, binding 0), the depth and the four targets of `forward::fs_gbuffer` (bindings
/// 4, 5, 9, 10 and 14, multisampled when `msaa > 1`), one sample at a time (`load_sample`), the
/// edge test between a pixel's samples (`differs`), and the shading inputs of a sample at its
/// own point or of a pixel at its centre (`shading_of`, `centre_shading`).
///
/// Sample positions are the standard ones of Vulkan and D3D (`sample_pattern`); points come from
/// the inverse projection, and a sample of an edge pixel is shaded where the ray through its
/// position meets its fragment's plane.
#[shader_dsl::library(
    axes(msaa: u32 = [1, 2, 4, 8]),
    uses(
        crate::shared::light_grid,
        crate::shared::surface_light,
        crate::shared::shadow_atlas,
        crate::shared::octahedral,
        crate::shared::sample_pattern,
    ),
)]
pub mod tbdr_gbuffer {
    /// The frame as the kernel needs it.
    pub struct TbdrParams {
        pub view: Mat4,
        pub projection: Mat4,
        pub inv_projection: Mat4,
        pub world_from_view: Mat4,
        pub eye: Vec3,
        /// Punctual lights in `LIGHTS` and `SPHERES`.
        pub light_count: u32,
        /// HDR radiance where no surface is.
        pub sky: Vec3,
        /// Directional lights at the start of `DIRECTIONAL`.
        pub directional_count: u32,
        pub screen: UVec2,
        /// 1: edge pixels are drawn red (the shading-frequency view).
        pub show_frequency: u32,
        /// 1: edge pixels set their bit in `EDGE_BITS`.
        pub record_edges: u32,
        /// Largest relative view-depth difference of a pixel's samples on one surface.
        pub depth_edge: f32,
        /// Smallest cosine between the shading normals of a pixel's samples on one surface.
        pub normal_edge: f32,
        /// Largest difference of a material channel of a pixel's samples on one surface.
        pub material_edge: f32,
        /// Non-zero: `projection` is orthographic (parallel view rays: the tile frustums' boxes
        /// and the view vector, the view's +Z axis everywhere).
        pub orthographic: u32,
    }

    /// One sample of the G-buffer.
    struct GSample {
        depth: f32,
        albedo_metallic: Vec4,
        normals: Vec4,
        radiance_roughness: Vec4,
        /// The view depth of the fragment that wrote the sample, at its pixel's centre.
        view_depth: f32,
    }

    /// A G-buffer sample as the light loop takes it.
    struct Shading {
        sky: bool,
        /// The surface point `surface_light`'s `light_contribution` shades.
        point: LitPoint,
        /// Ambient × albedo × occlusion + emissive.
        base: Vec3,
    }

    #[uniform(group = 0, binding = 0)]
    static PARAMS: TbdrParams;
    #[texture(group = 0, binding = 4)]
    #[when(msaa == 1)]
    static DEPTH: TextureDepth2d;
    #[texture(group = 0, binding = 4)]
    #[when(msaa > 1)]
    static DEPTH_MS: TextureDepthMultisampled2d;
    #[texture(group = 0, binding = 5)]
    #[when(msaa == 1)]
    static ALBEDO: Texture2d<f32>;
    #[texture(group = 0, binding = 5)]
    #[when(msaa > 1)]
    static ALBEDO_MS: TextureMultisampled2d<f32>;
    #[texture(group = 0, binding = 9)]
    #[when(msaa == 1)]
    static NORMALS: Texture2d<f32>;
    #[texture(group = 0, binding = 9)]
    #[when(msaa > 1)]
    static NORMALS_MS: TextureMultisampled2d<f32>;
    #[texture(group = 0, binding = 10)]
    #[when(msaa == 1)]
    static RADIANCE: Texture2d<f32>;
    #[texture(group = 0, binding = 10)]
    #[when(msaa > 1)]
    static RADIANCE_MS: TextureMultisampled2d<f32>;
    /// The G-buffer's view depth (`forward::GBufferOut::view_depth`).
    #[texture(group = 0, binding = 14, unfilterable)]
    #[when(msaa == 1)]
    static VIEW_DEPTH: Texture2d<f32>;
    #[texture(group = 0, binding = 14)]
    #[when(msaa > 1)]
    static VIEW_DEPTH_MS: TextureMultisampled2d<f32>;

    /// Sample `s` of pixel `p`.
    fn load_sample(p: UVec2, s: u32) -> GSample {
        let mut g = GSample {
            depth: 1.0,
            albedo_metallic: Vec4::ZERO,
            normals: Vec4::ZERO,
            radiance_roughness: Vec4::ZERO,
            view_depth: 0.0,
        };
        if msaa == 1 {
            g.depth = DEPTH.load(p, 0u32);
            g.albedo_metallic = ALBEDO.load(p, 0u32);
            g.normals = NORMALS.load(p, 0u32);
            g.radiance_roughness = RADIANCE.load(p, 0u32);
            g.view_depth = VIEW_DEPTH.load(p, 0u32).x;
        } else {
            g.depth = DEPTH_MS.load(p, s);
            g.albedo_metallic = ALBEDO_MS.load(p, s);
            g.normals = NORMALS_MS.load(p, s);
            g.radiance_roughness = RADIANCE_MS.load(p, s);
            g.view_depth = VIEW_DEPTH_MS.load(p, s).x;
        }
        g
    }

    fn depth_to_view(d: f32) -> f32 {
        view_depth(PARAMS.inv_projection, d)
    }

    fn largest(v: Vec4) -> f32 {
        v.x.max(v.y).max(v.z.max(v.w))
    }

    /// The view-space point of sample `s` of pixel `p` at depth-buffer value `depth`.
    fn view_point(p: UVec2, s: u32, depth: f32) -> Vec3 {
        view_point_at(p.as_vec2() + sample_offset(s), depth)
    }

    /// The view-space point at window position `at` (pixels) and depth-buffer value `depth`.
    fn view_point_at(at: Vec2, depth: f32) -> Vec3 {
        let size = PARAMS.screen.as_vec2();
        let ndc = Vec2::new(2.0 * at.x / size.x - 1.0, 1.0 - 2.0 * at.y / size.y);
        let h = PARAMS.inv_projection * Vec4::new(ndc.x, ndc.y, depth, 1.0);
        h.xyz() / h.w
    }

    /// Whether sample `s` (`b`) of pixel `p` belongs to another surface (or material) than
    /// sample 0 (`a`): sky against surface, a point off sample 0's plane (its geometric normal)
    /// by more than `depth_edge` of its view depth (so a slope within one triangle never
    /// counts), shading normals further apart than `normal_edge`, or a material channel off by
    /// more than `material_edge`.
    fn differs(p: UVec2, s: u32, a: GSample, b: GSample) -> bool {
        let sky_a = a.depth >= 1.0;
        let sky_b = b.depth >= 1.0;
        let mut edge = sky_a != sky_b;
        if !sky_a && !sky_b {
            let pa = view_point(p, 0u32, a.depth);
            let pb = view_point(p, s, b.depth);
            let plane = (PARAMS.view * octahedral_decode(a.normals.zw()).extend(0.0)).xyz();
            let gap = plane.dot(pb - pa).abs();
            let na = octahedral_decode(a.normals.xy());
            let nb = octahedral_decode(b.normals.xy());
            let material = largest((a.albedo_metallic - b.albedo_metallic).abs());
            let ra = a.radiance_roughness;
            let rb = b.radiance_roughness;
            let scale = 1.0 + largest(ra.abs()).max(largest(rb.abs()));
            let radiance = largest((ra - rb).abs()) / scale;
            edge = gap > PARAMS.depth_edge * -pa.z
                || na.dot(nb) < PARAMS.normal_edge
                || material.max(radiance) > PARAMS.material_edge;
        }
        edge
    }

    /// The shading inputs of sample `s` of pixel `p`, `g` being that sample: at the sample's
    /// own point, where its ray meets the plane of its fragment (the geometric normal through
    /// [`centre_point`]). A plane seen edge-on keeps the point of the sample's depth.
    fn shading_of(p: UVec2, s: u32, g: GSample) -> Shading {
        let c = centre_point(p, g);
        let n = (PARAMS.view * octahedral_decode(g.normals.zw()).extend(0.0)).xyz();
        let at = p.as_vec2() + sample_offset(s);
        let a = view_point_at(at, 0.0);
        let ray = view_point_at(at, 0.5) - a;
        let facing = n.dot(ray);
        let mut point = view_point(p, s, g.depth);
        if facing.abs() > 1.0e-6 * ray.length() {
            point = a + ray * (n.dot(c - a) / facing);
        }
        shading_at(p, point, g)
    }

    /// Where the fragment that wrote G-buffer sample `g` of pixel `p` was shaded: the view-space
    /// point at the pixel centre and the view depth the G-buffer stored.
    fn centre_point(p: UVec2, g: GSample) -> Vec3 {
        let centre = p.as_vec2() + Vec2::splat(0.5);
        let a = view_point_at(centre, 0.0);
        let ray = view_point_at(centre, 0.5) - a;
        a + ray * ((-g.view_depth - a.z) / ray.z)
    }

    /// The shading inputs of a pixel whose samples are all sample 0 (`g`): at the pixel centre,
    /// where the forward pass shades it too, at the view depth the G-buffer stored for sample 0
    /// (its fragment's, at the centre). Not from the depth buffer: a perspective depth near 1
    /// steps by about `z² / near · 2⁻²⁴` in view units, 3.5 mm at 1.8 m with the 0.056 mm near
    /// plane of a glTF camera (`TransmissionTest`'s), and lights close to a surface and sharp
    /// highlights turn that into steps of tens of colour levels.
    fn centre_shading(p: UVec2, g: GSample) -> Shading {
        shading_at(p, centre_point(p, g), g)
    }

    /// The unit vector from world point `p` towards the eye: along the view's +Z axis for an
    /// orthographic projection, whose view rays are parallel.
    fn toward_eye(p: Vec3) -> Vec3 {
        let mut v = PARAMS.eye - p;
        if PARAMS.orthographic != 0u32 {
            v = PARAMS.world_from_view.z_axis.xyz();
        }
        v.normalize()
    }

    /// The shading inputs of G-buffer sample `g` of pixel `p` at view-space point `view_p`.
    fn shading_at(p: UVec2, view_p: Vec3, g: GSample) -> Shading {
        let world = (PARAMS.world_from_view * view_p.extend(1.0)).xyz();
        let pixel_centre = p.as_vec2() + Vec2::splat(0.5);
        Shading {
            sky: g.depth >= 1.0,
            point: LitPoint {
                p: world,
                n: octahedral_decode(g.normals.xy()),
                v: toward_eye(world),
                albedo: g.albedo_metallic.xyz(),
                metallic: g.albedo_metallic.w,
                roughness: g.radiance_roughness.w,
                geometric_normal: octahedral_decode(g.normals.zw()),
                view_depth: -view_p.z,
                dither: dither_noise(pixel_centre),
            },
            base: g.radiance_roughness.xyz(),
        }
    }
}
