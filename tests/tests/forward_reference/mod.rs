//! The CPU reference of the forward-shading tests, written from the formulas and not from
//! the DSL code: lights and the surface as the reference sees them, the PBR light loop with
//! GGX, Smith and Schlick terms and the smooth range falloff, the tonemap curves with the sRGB
//! encode, and the heatmap's ramp.

use glam::Vec3;
use shaders_gen::forward::forward;

const PI: f32 = std::f32::consts::PI;

/// A light as the CPU reference sees it.
#[derive(Clone, Copy)]
pub struct Light {
    pub kind: u32,
    pub position: Vec3,
    pub direction: Vec3,
    pub color: Vec3,
    pub intensity: f32,
    pub range: f32,
    pub cos_inner: f32,
    pub cos_outer: f32,
}

impl Light {
    pub fn gpu(&self) -> forward::GpuLight {
        forward::GpuLight::new(
            self.position,
            self.range,
            self.color,
            self.intensity,
            self.direction,
            self.kind,
            self.cos_inner,
            self.cos_outer,
            shaders_gen::shared::shadow_atlas::NO_SHADOW,
        )
    }
}

/// Surface parameters of the test material (all textures white, normal map flat).
pub struct Surface {
    pub albedo: Vec3,
    pub metallic: f32,
    pub roughness: f32,
    pub emissive: Vec3,
    pub ambient: Vec3,
}

/// GGX normal distribution, with `alpha = roughness²`.
fn ggx(n_dot_h: f32, roughness: f32) -> f32 {
    let alpha2 = roughness.powi(4);
    let q = n_dot_h * n_dot_h * (alpha2 - 1.0) + 1.0;
    alpha2 / (PI * q * q)
}

/// Smith's geometry term with Schlick-GGX for direct lighting, `k = (r + 1)² / 8`.
fn smith_schlick_ggx(n_dot_v: f32, n_dot_l: f32, roughness: f32) -> f32 {
    let k = (roughness + 1.0).powi(2) / 8.0;
    let g1 = |x: f32| x / (x * (1.0 - k) + k);
    g1(n_dot_v) * g1(n_dot_l)
}

fn fresnel_schlick(v_dot_h: f32, f0: Vec3) -> Vec3 {
    f0 + (Vec3::ONE - f0) * (1.0 - v_dot_h).powi(5)
}

/// `saturate(1 − (d/range)⁴)² / max(d², 0.01²)`; range 0 is infinite.
fn falloff(d: f32, range: f32) -> f32 {
    let window = if range > 0.0 {
        (1.0 - (d / range).powi(4)).clamp(0.0, 1.0).powi(2)
    } else {
        1.0
    };
    window / (d * d).max(0.01 * 0.01)
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Outgoing radiance at `p` (normal `n`, towards the eye) from `lights`, plus ambient and
/// emission, evaluated from the formulas in f64-free plain f32 Rust.
pub fn shade_cpu(p: Vec3, n: Vec3, eye: Vec3, s: &Surface, lights: &[Light]) -> Vec3 {
    let v = (eye - p).normalize();
    let f0 = Vec3::splat(0.04) * (1.0 - s.metallic) + s.albedo * s.metallic;
    let mut color = s.ambient * s.albedo + s.emissive;
    for light in lights {
        let (l, radiance) = if light.kind == 2 {
            (-light.direction, light.color * light.intensity)
        } else {
            let to_light = light.position - p;
            let d = to_light.length();
            let l = to_light / d;
            let mut a = falloff(d, light.range);
            if light.kind == 1 {
                a *= smoothstep(light.cos_outer, light.cos_inner, light.direction.dot(-l));
            }
            (l, light.color * light.intensity * a)
        };
        let n_dot_l = n.dot(l).max(0.0);
        if n_dot_l == 0.0 {
            continue;
        }
        let h = (l + v).normalize();
        let n_dot_v = n.dot(v).max(1e-4);
        let f = fresnel_schlick(v.dot(h).max(0.0), f0);
        let specular = f
            * ggx(n.dot(h).max(0.0), s.roughness)
            * smith_schlick_ggx(n_dot_v, n_dot_l, s.roughness)
            / (4.0 * n_dot_v * n_dot_l).max(1e-4);
        let diffuse = (Vec3::ONE - f) * (1.0 - s.metallic) * s.albedo / PI;
        color += (diffuse + specular) * radiance * n_dot_l;
    }
    color
}

/// ACES filmic, Narkowicz's fit, clamped to [0, 1].
pub fn aces_cpu(x: f32) -> f32 {
    ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// Khronos PBR Neutral, from its published definition.
pub fn neutral_cpu(c: Vec3) -> Vec3 {
    let start_compression = 0.8 - 0.04;
    let desaturation = 0.15;
    let x = c.min_element();
    let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
    let c = c - offset;
    let peak = c.max_element();
    if peak < start_compression {
        return c;
    }
    let d = 1.0 - start_compression;
    let new_peak = 1.0 - d * d / (peak + d - start_compression);
    let c = c * (new_peak / peak);
    let g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
    c * (1.0 - g) + Vec3::splat(new_peak) * g
}

pub fn srgb_encode(l: f32) -> u8 {
    let l = l.clamp(0.0, 1.0);
    let s = if l <= 0.003_130_8 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

/// The heatmap ramp from its stops: black, blue, green, yellow, red at 0, ¼, ½, ¾, 1.
pub fn ramp_cpu(t: f32) -> Vec3 {
    let stops = [
        Vec3::ZERO,
        Vec3::Z,
        Vec3::Y,
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::X,
    ];
    let s = t.clamp(0.0, 1.0) * 4.0;
    let i = (s.ceil() as usize).clamp(1, 4);
    stops[i - 1].lerp(stops[i], s - (i - 1) as f32)
}
