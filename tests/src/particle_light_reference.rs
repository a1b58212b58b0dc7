//! The particle lighting response evaluated on the CPU, written from its specification in
//! `docs/particle_lighting.md` (not from the shaders): where each atlas texel lies on its
//! particle's billboard, the half-Lambert response to every light with its attenuation, the
//! shadow visibility (its own projection and bilinear depth comparisons over the shadow atlas
//! depth read back from the GPU), and the sky and ground ambient. Also the `Rg11b10Ufloat` packing, written from
//! the format's definition, to upload a CPU-lit atlas.

use glam::{UVec2, Vec2, Vec3, Vec4, Vec4Swizzles};
use shaders_gen::particles::particle_light::{
    GpuEmitter, GpuLight, GpuParticle, ParticleView, ShadowView,
};

use crate::frame_probe::ShadowInputs;

/// `GpuLight::kind` of a directional light; `GpuLight::shadow` of a light without a shadow.
const DIRECTIONAL: u32 = 2;
const SPOT: u32 = 1;
const NO_SHADOW: u32 = u32::MAX;
/// Fraction of a cascade over which it dithers into the next.
const CASCADE_BLEND: f32 = 0.15;

/// Everything the response depends on, as the frame's buffers hold it.
#[derive(Debug, Clone)]
pub struct LightingScene {
    pub view: ParticleView,
    pub punctual: Vec<GpuLight>,
    pub directional: Vec<GpuLight>,
    pub emitters: Vec<GpuEmitter>,
    pub particles: Vec<GpuParticle>,
    pub shadow_views: Vec<ShadowView>,
    pub shadows: ShadowInputs,
}

/// One particle's region of the atlas: corner and side, texels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Region {
    pub slot: u32,
    pub corner: UVec2,
    pub side: u32,
}

impl Region {
    /// The region packed as `x | y << 12 | class << 24` (side `2 << class`).
    pub fn unpack(slot: u32, packed: u32) -> Self {
        Self {
            slot,
            corner: UVec2::new(packed & 0xfff, (packed >> 12) & 0xfff),
            side: 2 << (packed >> 24),
        }
    }
}

/// Hermite smoothstep: 0 below `e0`, 1 above `e1`, `t² (3 − 2t)` between.
fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Interleaved gradient noise of position `(x, y)`.
pub fn gradient_noise(x: f32, y: f32) -> f32 {
    (52.982_918 * (0.067_110_56 * x + 0.005_837_15 * y).fract()).fract()
}

impl LightingScene {
    /// The particle's billboard point and rounded normal at `uv`.
    pub fn billboard(&self, particle: &GpuParticle, uv: Vec2) -> (Vec3, Vec3) {
        let e = &self.emitters[particle.emitter as usize];
        let life = (particle.age / particle.lifetime).clamp(0.0, 1.0);
        let h = e.size.x + (e.size.y - e.size.x) * life;
        let q = uv * 2.0 - Vec2::ONE;
        let across = self.view.right * q.x - self.view.up * q.y;
        let point = particle.position + across * h;
        let to_eye = (self.view.eye - particle.position).normalize();
        let bulge = (1.0 - q.length_squared()).max(0.0).sqrt();
        (point, (across + to_eye * bulge).normalize())
    }

    /// `L(p, n)` of the specification, with `dither` the cascade dither of the texel.
    pub fn response(&self, p: Vec3, n: Vec3, dither: f32) -> Vec3 {
        let depth = -(self.view.view * p.extend(1.0)).z;
        // Hemisphere ambient: ground below, sky above, linear in the normal's world up part.
        let up = (n.y + 1.0) / 2.0;
        let mut sum = self.view.ambient_ground * (1.0 - up) + self.view.ambient_sky * up;
        for light in self.directional.iter().chain(&self.punctual) {
            let (l, attenuation) = self.incidence(light, p);
            let wrap = (n.dot(l) + 1.0) / 2.0;
            let arriving = attenuation * wrap * wrap / std::f32::consts::PI;
            if arriving > 0.0 {
                let visibility = self.visibility(light, p, depth, dither);
                sum += light.color * (light.intensity * arriving * visibility);
            }
        }
        sum
    }

    /// The unit direction towards `light` from `p` and the attenuation `A`.
    fn incidence(&self, light: &GpuLight, p: Vec3) -> (Vec3, f32) {
        if light.kind == DIRECTIONAL {
            return (-light.direction, 1.0);
        }
        let to_light = light.position - p;
        let d2 = to_light.length_squared();
        let l = to_light / d2.sqrt();
        let window = if light.range > 0.0 {
            let x = d2 / (light.range * light.range);
            (1.0 - x * x).clamp(0.0, 1.0).powi(2)
        } else {
            1.0
        };
        let cone = if light.kind == SPOT {
            smoothstep(light.cos_outer, light.cos_inner, light.direction.dot(-l))
        } else {
            1.0
        };
        (l, window * cone / d2.max(1e-4))
    }

    /// `V(p)`: the view the light's record names, then nine bilinear depth comparisons.
    fn visibility(&self, light: &GpuLight, p: Vec3, depth: f32, dither: f32) -> f32 {
        if light.shadow == NO_SHADOW {
            return 1.0;
        }
        let first = light.shadow as usize;
        let view = match self.shadow_views[first].faces {
            6 => first + cube_face(p - light.position),
            4 => match self.cascade(first, depth, dither) {
                Some(c) => first + c,
                None => return 1.0,
            },
            _ => first,
        };
        self.pcf(&self.shadow_views[view], p)
    }

    /// The cascade of view depth `z` among the four from `first`, dithered near its far end.
    fn cascade(&self, first: usize, z: f32, dither: f32) -> Option<usize> {
        let far = |c: usize| self.shadow_views[first + c].split_far;
        let c = (0..4).find(|&c| z <= far(c))?;
        if c == 3 {
            return Some(3);
        }
        let start = if c == 0 { 0.0 } else { far(c - 1) };
        let end = far(c);
        let blend = end - CASCADE_BLEND * (end - start);
        let t = (z - blend) / (end - blend);
        Some(if t > 0.0 && dither < t { c + 1 } else { c })
    }

    /// The mean of nine bilinear comparisons a texel apart round `p`'s place in `view`.
    fn pcf(&self, view: &ShadowView, p: Vec3) -> f32 {
        let clip: Vec4 = view.clip_from_world * p.extend(1.0);
        let ndc = clip.xyz() / clip.w;
        if ndc.x.abs() > 1.0 || ndc.y.abs() > 1.0 || !(0.0..=1.0).contains(&ndc.z) {
            return 1.0;
        }
        let texel = 1.0 / self.shadows.side as f32;
        let (corner, size) = (view.rect.xy(), view.rect.zw());
        let centre = corner + Vec2::new(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * size;
        let lo = corner + Vec2::splat(texel / 2.0);
        let hi = corner + size - Vec2::splat(texel / 2.0);
        let mut lit = 0.0;
        for b in -1..=1 {
            for a in -1..=1 {
                let at = (centre + Vec2::new(a as f32, b as f32) * texel).clamp(lo, hi);
                lit += self.compare_bilinear(at, ndc.z);
            }
        }
        lit / 9.0
    }

    /// One bilinear depth comparison at atlas UV `uv`: lit where `reference ≥` the stored depth.
    fn compare_bilinear(&self, uv: Vec2, reference: f32) -> f32 {
        let n = self.shadows.side as i64;
        let g = uv * n as f32 - Vec2::splat(0.5);
        let (base, f) = (g.floor(), g - g.floor());
        let lit = |dx: i64, dy: i64| {
            let x = (base.x as i64 + dx).clamp(0, n - 1);
            let y = (base.y as i64 + dy).clamp(0, n - 1);
            let stored = self.shadows.atlas[(y * n + x) as usize];
            if reference >= stored { 1.0 } else { 0.0 }
        };
        let top = lit(0, 0) * (1.0 - f.x) + lit(1, 0) * f.x;
        let bottom = lit(0, 1) * (1.0 - f.x) + lit(1, 1) * f.x;
        top * (1.0 - f.y) + bottom * f.y
    }

    /// The response of every texel of `region`, row by row, with its atlas position.
    pub fn light_region(&self, region: Region) -> Vec<(UVec2, Vec3)> {
        let particle = &self.particles[region.slot as usize];
        let mut out = Vec::with_capacity((region.side * region.side) as usize);
        for j in 0..region.side {
            for i in 0..region.side {
                let uv = (Vec2::new(i as f32, j as f32) + 0.5) / region.side as f32;
                let (p, n) = self.billboard(particle, uv);
                let texel = region.corner + UVec2::new(i, j);
                let dither = gradient_noise(texel.x as f32, texel.y as f32);
                out.push((texel, self.response(p, n, dither)));
            }
        }
        out
    }
}

/// The cube face of direction `d` from a point light: `+X, −X, +Y, −Y, +Z, −Z` as 0–5, by the
/// major axis (ties to X before Y before Z, zero counted positive).
fn cube_face(d: Vec3) -> usize {
    let a = d.abs();
    let (axis, positive) = if a.x >= a.y && a.x >= a.z {
        (0, d.x >= 0.0)
    } else if a.y >= a.z {
        (1, d.y >= 0.0)
    } else {
        (2, d.z >= 0.0)
    };
    2 * axis + usize::from(!positive)
}

/// One unsigned float of `mantissa` bits and a 5-bit exponent (bias 15), rounded to nearest:
/// the representable value nearest `v` (clamped to `[0, 65024]`), then its bits.
fn to_ufloat(v: f32, mantissa: u32) -> u32 {
    let v = if v.is_nan() {
        0.0
    } else {
        v.clamp(0.0, 65024.0)
    };
    if v < 2f32.powi(-14) {
        // Denormal range: steps of 2^-14 / 2^mantissa.
        let m = (v * 2f32.powi(14) * (1u32 << mantissa) as f32).round() as u32;
        return m; // m == 1 << mantissa is exponent 1, mantissa 0: the right bits too
    }
    let e = v.log2().floor() as i32;
    let step = 2f32.powi(e - mantissa as i32);
    let rounded = (v / step).round() * step;
    let e = rounded.log2().floor() as i32;
    let m = ((rounded / 2f32.powi(e) - 1.0) * (1u32 << mantissa) as f32).round() as u32;
    (((e + 15) as u32) << mantissa) | m
}

/// Linear RGB as `Rg11b10Ufloat` bits (red bits 0–10, green 11–21, blue 22–31).
pub fn pack_rg11b10(c: Vec3) -> u32 {
    to_ufloat(c.x, 6) | (to_ufloat(c.y, 6) << 11) | (to_ufloat(c.z, 5) << 22)
}

/// The view, lights, emitters, particles and shadow views of a frame's buffers.
pub fn scene_from_bytes(
    view: &[u8],
    punctual: &[u8],
    directional: &[u8],
    emitters: &[u8],
    particles: &[u8],
    shadows: ShadowInputs,
) -> LightingScene {
    let view: ParticleView = bytemuck::pod_read_unaligned(&view[..size_of::<ParticleView>()]);
    let mut directional: Vec<GpuLight> = bytemuck::pod_collect_to_vec(directional);
    directional.truncate(view.directional_count as usize);
    let mut punctual: Vec<GpuLight> = bytemuck::pod_collect_to_vec(punctual);
    punctual.truncate(view.light_count as usize);
    LightingScene {
        view,
        punctual,
        directional,
        emitters: bytemuck::pod_collect_to_vec(emitters),
        particles: bytemuck::pod_collect_to_vec(particles),
        shadow_views: bytemuck::pod_collect_to_vec(&shadows.views),
        shadows,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packing_rounds_to_the_nearest_unsigned_float() {
        // 1.0: exponent 15, mantissa 0, in every channel.
        assert_eq!(
            pack_rg11b10(Vec3::ONE),
            15 << 6 | (15 << 6) << 11 | (15 << 5) << 22
        );
        // 1 + 1/64 is exact in 6 bits; 1.98 rounds down to 1 + 63/64, 1.995 up to 2.
        assert_eq!(to_ufloat(1.0 + 1.0 / 64.0, 6), 15 << 6 | 1);
        assert_eq!(to_ufloat(-3.0, 6), 0);
        assert_eq!(to_ufloat(1.0e6, 6), 30 << 6 | 63);
        assert_eq!(to_ufloat(1.98, 6), 15 << 6 | 63);
        assert_eq!(to_ufloat(1.995, 6), 16 << 6);
    }

    #[test]
    fn cube_faces_follow_the_major_axis() {
        assert_eq!(cube_face(Vec3::new(2.0, 1.0, 1.0)), 0);
        assert_eq!(cube_face(Vec3::new(-2.0, 1.0, 1.0)), 1);
        assert_eq!(cube_face(Vec3::new(0.0, -3.0, 1.0)), 3);
        assert_eq!(cube_face(Vec3::new(0.0, 0.0, -1.0)), 5);
        assert_eq!(cube_face(Vec3::new(1.0, 1.0, 1.0)), 0);
    }
}
