//! Physically based shading of one light: the light record, the metallic-roughness BRDF, and
//! the half-Lambert response of particles.

/// `GpuLight` (the record in the light buffers), its `KIND_*` values, `light_incidence` (the
/// direction and attenuation every response shares), `shade_light`: GGX distribution,
/// Smith/Schlick-GGX geometry, Schlick Fresnel and Lambert diffuse; and `particle_light`, the
/// view-independent half-Lambert response of particles; `hemisphere_ambient`, the sky and ground
/// ambient of every lit surface and particle.
///
/// Falloff: `saturate(1 - (d / range)^4)^2 / max(d², 0.01²)`, with no window when `range` is 0
/// (infinite). Spot cone: `smoothstep(cos_outer, cos_inner, cos θ)`.
#[shader_dsl::library]
pub mod pbr {
    /// One light. `kind`: 0 point, 1 spot, 2 directional. `direction` is where a spot or
    /// directional light points (unit length).
    pub struct GpuLight {
        pub position: Vec3,
        /// 0: infinite (no window).
        pub range: f32,
        /// Linear colour.
        pub color: Vec3,
        /// Point/spot: candela (W/sr-like); directional: lux.
        pub intensity: f32,
        pub direction: Vec3,
        pub kind: u32,
        pub cos_inner: f32,
        pub cos_outer: f32,
        /// The light's first view in the shadow atlas (`shadow_atlas::SHADOW_VIEWS`), or
        /// `shadow_atlas::NO_SHADOW`.
        pub shadow: u32,
    }

    pub const KIND_POINT: u32 = 0;
    pub const KIND_SPOT: u32 = 1;
    pub const KIND_DIRECTIONAL: u32 = 2;
    /// Smallest roughness (keeps the GGX lobe finite).
    pub const MIN_ROUGHNESS: f32 = 0.045;
    const PI: f32 = core::f32::consts::PI;

    /// Where `light` comes from at `p` and how much of it arrives: `xyz` the unit direction
    /// towards the light, `w` its attenuation (falloff, window and spot cone; 1 for a
    /// directional light).
    pub fn light_incidence(light: GpuLight, p: Vec3) -> Vec4 {
        let mut l = -light.direction;
        let mut attenuation = 1.0;
        if light.kind != KIND_DIRECTIONAL {
            let to_light = light.position - p;
            let d2 = to_light.dot(to_light);
            l = to_light.normalize();
            attenuation = 1.0 / d2.max(0.0001);
            if light.range > 0.0 {
                let r = d2 / (light.range * light.range);
                let window = (1.0 - r * r).saturate();
                attenuation = attenuation * window * window;
            }
            if light.kind == KIND_SPOT {
                let cos_angle = light.direction.dot(-l);
                attenuation = attenuation * cos_angle.smoothstep(light.cos_outer, light.cos_inner);
            }
        }
        l.extend(attenuation)
    }

    /// Hemisphere ambient radiance at unit normal `n`: `sky` from straight up (world +Y),
    /// `ground` from straight down, blended linearly by `n.y * 0.5 + 0.5` in between.
    pub fn hemisphere_ambient(sky: Vec3, ground: Vec3, n: Vec3) -> Vec3 {
        ground + (sky - ground) * (n.y * 0.5 + 0.5)
    }

    /// The view-independent response of a particle at `p` to one light: Valve's half-Lambert,
    /// `((n · l + 1) / 2)² / π`, on the particle's rounded normal `n`, times the light's arriving
    /// radiance (the `1 / π` of a Lambert albedo; the draw multiplies by the particle's colour). Light wraps around a puff instead of cutting off at its terminator, and no
    /// term depends on the eye, so it can be lit once per atlas texel.
    pub fn particle_light(light: GpuLight, p: Vec3, n: Vec3) -> Vec3 {
        let incidence = light_incidence(light, p);
        let wrap = 0.5 * n.dot(incidence.xyz()) + 0.5;
        light.color * (light.intensity * incidence.w * wrap * wrap / PI)
    }

    /// Radiance one light reflects towards `v` (GGX / Smith-Schlick / Schlick / Lambert).
    pub fn shade_light(
        light: GpuLight,
        p: Vec3,
        n: Vec3,
        v: Vec3,
        albedo: Vec3,
        metallic: f32,
        roughness: f32,
    ) -> Vec3 {
        let incidence = light_incidence(light, p);
        let l = incidence.xyz();
        let attenuation = incidence.w;
        let nl = n.dot(l).max(0.0);
        // The half vector; when the light sits straight behind the point (l = −v) it is
        // undefined, and any unit vector does (the terms it feeds are then multiplied by 0).
        let lv = l + v;
        let h = lv / lv.length().max(1.0e-6);
        let nv = n.dot(v).max(0.0001);
        let nh = n.dot(h).max(0.0);
        let vh = v.dot(h).max(0.0);
        let a = roughness * roughness;
        let a2 = a * a;
        let dd = nh * nh * (a2 - 1.0) + 1.0;
        let distribution = a2 / (PI * dd * dd);
        let k = (roughness + 1.0) * (roughness + 1.0) / 8.0;
        let geometry = nv / (nv * (1.0 - k) + k) * (nl / (nl * (1.0 - k) + k));
        let f0 = Vec3::splat(0.04).lerp(albedo, metallic);
        // `v · h` can round past 1, and `pow` of a negative base is NaN (WGSL), which would
        // poison the sum even for a light whose window is 0 here.
        let fresnel = f0 + (Vec3::ONE - f0) * (1.0 - vh.min(1.0)).powf(5.0);
        let specular = fresnel * (distribution * geometry / (4.0 * nv * nl).max(0.0001));
        let diffuse = (Vec3::ONE - fresnel) * (1.0 - metallic) * albedo / PI;
        (diffuse + specular) * light.color * (light.intensity * attenuation * nl)
    }
}
