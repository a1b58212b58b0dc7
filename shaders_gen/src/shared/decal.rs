//! Decal application, shared by every pass that shades a surface: the forward pass today, the
//! G-buffer pass of compute shading later. Decals are applied to the surface's material before
//! lighting (DOOM 2016, reference 004).

/// The decal records and atlas as shading reads them, and `apply_decal`, which blends one decal
/// into a surface's material.
///
/// A decal is an oriented box; its image is projected along the box's −Z axis. `GpuDecal`'s
/// rows take a world position to box space scaled to `[−1, 1]³`, so a point is inside when
/// every coordinate is within 1; the image's `u` runs along box +X and its top along box +Y.
/// The atlas holds every material at one rectangle (`uv_rect`) in four textures of the same
/// layout: base colour (sRGB, alpha = coverage), tangent-space normal, occlusion-roughness-
/// metalness, and emissive (sRGB). Mip levels are chosen from gradients of the box projection
/// (the chain rule on the screen derivatives of the world position), so `apply_decal` may run in
/// non-uniform control flow (a list loop) and still filter right; the atlas's gutters keep every
/// level from bleeding into a neighbour.
///
/// The decal's opacity is its base-colour alpha × `blend` × an angle fade (the surface normal
/// against box +Z, from whole at `angle_start` to gone at `angle_end`) × a distance fade. The
/// base colour, the normal (the decal's tangent-space normal in a frame built on the surface
/// normal with the box's +X as tangent), occlusion, roughness, metalness and emissive are each
/// blended by that opacity, for the channels the material has.
#[shader_dsl::library]
pub mod decal_apply {
    /// One decal as shading reads it (in layer order: later decals are applied over earlier).
    pub struct GpuDecal {
        /// Row 0 of world → box (`[−1, 1]³`): box `x = row0.xyz · p + row0.w`.
        pub row0: Vec4,
        pub row1: Vec4,
        pub row2: Vec4,
        /// The material's rectangle in the atlas: corner `xy`, size `zw` (UV).
        pub uv_rect: Vec4,
        /// `x`: cosine where the angle fade ends (gone), `y`: its slope in cosine (whole at
        /// `1 / y` above `x`); `z`: camera distance where the distance fade ends, `w`: its slope.
        pub fade: Vec4,
        /// Opacity multiplier, 0 to 1.
        pub blend: f32,
        /// Bit 1 normal, bit 2 occlusion-roughness-metalness, bit 3 emissive (the atlas
        /// channel order; base colour, bit 0, is always present).
        pub channels: u32,
    }

    /// A surface's material as lighting takes it; decals blend into it.
    pub struct DecalSurface {
        pub albedo: Vec3,
        /// Shading normal (unit, world space).
        pub normal: Vec3,
        pub occlusion: f32,
        pub roughness: f32,
        pub metallic: f32,
        pub emissive: Vec3,
    }

    /// The screen-space derivatives of the shaded point's world position (taken once, in uniform
    /// control flow) and what the fades need.
    pub struct DecalFrame {
        pub position: Vec3,
        pub dpdx: Vec3,
        pub dpdy: Vec3,
        /// Unit geometric normal (the angle fade's).
        pub geometric_normal: Vec3,
        /// Distance from the camera (the distance fade's).
        pub distance: f32,
    }

    /// `GpuDecal::channels` bit of a normal map.
    pub const DECAL_NORMAL: u32 = 2;
    /// `GpuDecal::channels` bit of an occlusion-roughness-metalness map.
    pub const DECAL_ORM: u32 = 4;
    /// `GpuDecal::channels` bit of an emissive map.
    pub const DECAL_EMISSIVE: u32 = 8;

    #[storage(group = 0, binding = 9)]
    static DECALS: [GpuDecal];
    #[texture(group = 0, binding = 10)]
    static DECAL_BASE_COLOR: Texture2d<f32>;
    #[texture(group = 0, binding = 11)]
    static DECAL_NORMAL_MAP: Texture2d<f32>;
    #[texture(group = 0, binding = 12)]
    static DECAL_ORM_MAP: Texture2d<f32>;
    #[texture(group = 0, binding = 13)]
    static DECAL_EMISSIVE_MAP: Texture2d<f32>;
    #[sampler(group = 0, binding = 14)]
    static DECAL_SAMPLER: Sampler;

    /// Blends decal `index` of `DECALS` into `s` where `f`'s point lies inside its box.
    pub fn apply_decal(index: u32, s: DecalSurface, f: DecalFrame) -> DecalSurface {
        let d = DECALS[index];
        let p = f.position;
        let local = Vec3::new(
            d.row0.xyz().dot(p) + d.row0.w,
            d.row1.xyz().dot(p) + d.row1.w,
            d.row2.xyz().dot(p) + d.row2.w,
        );
        let reach = local.abs();
        let mut out = s;
        if reach.x <= 1.0 && reach.y <= 1.0 && reach.z <= 1.0 {
            let axis_z = d.row2.xyz().normalize();
            let facing = f.geometric_normal.dot(axis_z);
            let angle = ((facing - d.fade.x) * d.fade.y).saturate();
            let distance = ((d.fade.z - f.distance) * d.fade.w).saturate();
            let weight = d.blend * angle * distance;
            if weight > 0.0 {
                // Box x → u and box y → v (image rows run down), both from [−1, 1] to the rect.
                let half = d.uv_rect.zw() * Vec2::new(0.5, -0.5);
                let uv = d.uv_rect.xy() + 0.5 * d.uv_rect.zw() + local.xy() * half;
                let ddx = Vec2::new(d.row0.xyz().dot(f.dpdx), d.row1.xyz().dot(f.dpdx)) * half;
                let ddy = Vec2::new(d.row0.xyz().dot(f.dpdy), d.row1.xyz().dot(f.dpdy)) * half;
                let base = DECAL_BASE_COLOR.sample_grad(DECAL_SAMPLER, uv, ddx, ddy);
                let a = base.w * weight;
                out.albedo = s.albedo.lerp(base.xyz(), a);
                if (d.channels & DECAL_NORMAL) != 0u32 {
                    let t = DECAL_NORMAL_MAP
                        .sample_grad(DECAL_SAMPLER, uv, ddx, ddy)
                        .xyz()
                        * 2.0
                        - 1.0;
                    // The decal's tangent frame reoriented onto the surface normal: box +X
                    // made perpendicular to it, the bitangent completing a right-handed frame.
                    let n = s.normal;
                    let mut along = d.row0.xyz() - n * n.dot(d.row0.xyz());
                    if along.length_squared() < 1.0e-12 {
                        // Box +X along the normal (a surface edge-on to the box): use box +Y.
                        along = d.row1.xyz() - n * n.dot(d.row1.xyz());
                    }
                    let tangent = along.normalize();
                    let bitangent = n.cross(tangent);
                    let decal_normal = (tangent * t.x + bitangent * t.y + n * t.z).normalize();
                    out.normal = n.lerp(decal_normal, a).normalize();
                }
                if (d.channels & DECAL_ORM) != 0u32 {
                    let orm = DECAL_ORM_MAP.sample_grad(DECAL_SAMPLER, uv, ddx, ddy);
                    out.occlusion = s.occlusion + (orm.x - s.occlusion) * a;
                    out.roughness = s.roughness + (orm.y - s.roughness) * a;
                    out.metallic = s.metallic + (orm.z - s.metallic) * a;
                }
                if (d.channels & DECAL_EMISSIVE) != 0u32 {
                    let e = DECAL_EMISSIVE_MAP.sample_grad(DECAL_SAMPLER, uv, ddx, ddy);
                    out.emissive = s.emissive.lerp(e.xyz(), a);
                }
            }
        }
        out
    }
}
