//! Traditional deferred shading's light volumes: each punctual light drawn as the cube around
//! its bounding sphere, shaded from the G-buffer with the TBDR kernel's shading points and the
//! one light response of every path, blended additively.

/// The light volumes of `RenderPath::Deferred` (reference 000's "deferred shading" method):
/// `vs_light_volume` places the cube around a light's sphere (`light_spheres`),
/// `fs_light_volume` shades one light at one pixel from the G-buffer (`tbdr_gbuffer`'s samples
/// and shading points, `surface_light`'s `light_contribution`), per sample where the deferred
/// base pass (a `tbdr` dispatch with no punctual lights) marked the pixel an edge in `EDGE_BITS`.
///
/// Group 0 is the `tbdr` module's, less what only its compute entry writes: the same parameters,
/// G-buffer, lights, spheres and shadow atlas, and the edge bits read-only.
#[shader_dsl::shader(
    axes(msaa: u32 = [1, 2, 4, 8]),
    uses(
        crate::deferred::gbuffer_read::tbdr_gbuffer,
        crate::shared::light_spheres,
        crate::shared::surface_light,
    ),
)]
pub mod light_volume {
    /// The deferred base pass's edge pixels, a bit per pixel, row-major (`tbdr`'s `EDGE_BITS`).
    #[storage(group = 0, binding = 12)]
    static EDGE_BITS: [u32];

    /// A light volume's vertex: the light's index, for its fragments.
    pub struct VolumeOut {
        #[builtin(position)]
        pub clip: Vec4,
        #[location(0)]
        #[interpolate(flat)]
        pub light: u32,
    }

    /// Corner `vi` (0..36) of the cube `[−1, 1]³` as twelve triangles, counter-clockwise seen
    /// from outside: face `vi / 6` is `±` axis `vi / 12`, split into two triangles.
    fn cube_corner(vi: u32) -> Vec3 {
        let face = vi / 6u32;
        let k = vi % 6u32;
        let u = select(k == 1u32 || k == 2u32 || k == 4u32, 1.0, -1.0);
        let v = select(k == 2u32 || k == 4u32 || k == 5u32, 1.0, -1.0);
        let s = select(face % 2u32 == 0u32, 1.0, -1.0);
        // Along the face's axis, then the next two axes in cyclic order (the `u` axis flipped
        // with the face so that (u, v, outward) stays right-handed).
        let q = Vec3::new(s, s * u, v);
        let axis = face / 2u32;
        select(axis == 0u32, q, select(axis == 1u32, q.zxy(), q.yzx()))
    }

    /// Traditional deferred shading's light volume: the cube around punctual light
    /// `instance`'s bounding sphere (`SPHERES`). The pipeline draws only its back faces, with
    /// no depth test, so every pixel the sphere may cover is shaded once whether the camera is
    /// outside the volume or inside it; clip depth is held inside the far plane, so a volume
    /// reaching past it still covers its pixels.
    #[vertex]
    pub fn vs_light_volume(
        #[builtin(vertex_index)] vi: u32,
        #[builtin(instance_index)] light: u32,
    ) -> VolumeOut {
        let sphere = SPHERES[light];
        let world = sphere.xyz() + cube_corner(vi) * sphere.w;
        let mut clip = PARAMS.projection * (PARAMS.view * world.extend(1.0));
        if clip.w > 0.0 {
            clip.z = clip.z.min(clip.w * 0.999_999);
        }
        VolumeOut { clip, light }
    }

    /// One light at one pixel, from the G-buffer: at the pixel centre (sample 0's view depth), or,
    /// where the deferred base pass marked the pixel an edge (`EDGE_BITS`), the mean over its
    /// samples at their own points; the same shading as `tbdr::shade`. Blended additively into the
    /// base pass's resolved image; a pixel the light does not reach is discarded, and so is an
    /// edge pixel in the shading-frequency view (the base pass drew it red).
    #[fragment]
    pub fn fs_light_volume(input: VolumeOut) -> Vec4 {
        let pixel = input.clip.xy().floor().as_uvec2();
        let light = LIGHTS[input.light];
        let bit = pixel.y * PARAMS.screen.x + pixel.x;
        let edge = (EDGE_BITS[bit / 32u32] & (1u32 << (bit % 32u32))) != 0u32;
        if edge && PARAMS.show_frequency != 0u32 {
            discard();
        }
        let g0 = load_sample(pixel, 0u32);
        let mut color = Vec3::ZERO;
        if edge {
            for s in 0u32..msaa {
                let mut g = g0;
                if s > 0u32 {
                    g = load_sample(pixel, s);
                }
                if g.depth < 1.0 {
                    color += light_contribution(light, shading_of(pixel, s, g).point);
                }
            }
            color = color / msaa as f32;
        } else if g0.depth < 1.0 {
            color = light_contribution(light, centre_shading(pixel, g0).point);
        }
        if color.x + color.y + color.z <= 0.0 {
            discard();
        }
        color.extend(0.0)
    }
}
