//! Seeded set-up for demos, tools and tests: procedural lights, the lights chosen to cast
//! shadows, the instance that moves, and the built-in courtyard's look.

use glam::Vec3;

use crate::frame::{FrameCamera, RendererConfig};
use crate::scene::{Aabb, LightKind, Scene, SceneLight};

/// A tiny deterministic generator (SplitMix64), so seeded scenes never change between runs.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator whose sequence `seed` fixes.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 uniform bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        let unit = (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32;
        lo + (hi - lo) * unit
    }
}

/// Where tools put procedural lights in a scene, and their default radii: the courtyard's open
/// space with radii that make pools of light (`builtin`), else a file scene's bounds with radii
/// of 3–20% of its size.
pub fn light_space(scene: &Scene, builtin: bool) -> (Aabb, (f32, f32)) {
    use crate::scene::procedural::{COURTYARD_LIGHT_RADII, COURTYARD_LIGHT_REGION};
    if builtin {
        return (COURTYARD_LIGHT_REGION, COURTYARD_LIGHT_RADII);
    }
    let size = (scene.bounds.max - scene.bounds.min).length();
    (scene.bounds, (size * 0.03, size * 0.2))
}

/// The built-in courtyard's look on top of `config`: its calibrated exposure, its ambient (a
/// dusk sky's fill light) and its sky colour.
pub fn courtyard_look(config: RendererConfig) -> RendererConfig {
    use crate::scene::procedural::{COURTYARD_AMBIENT, COURTYARD_EV, COURTYARD_SKY};
    RendererConfig {
        exposure: 2f32.powf(COURTYARD_EV),
        ambient: crate::frame_data::Ambient::uniform(COURTYARD_AMBIENT),
        sky: COURTYARD_SKY,
        ..config
    }
}

/// `count` point lights spread through `bounds` (grown by 20%), with ranges drawn from
/// `[min_radius, max_radius]` and bright enough to show at their range's middle.
pub fn procedural_lights(
    bounds: Aabb,
    count: usize,
    seed: u64,
    min_radius: f32,
    max_radius: f32,
) -> Vec<SceneLight> {
    let mut rng = Rng::new(seed);
    let (lo, hi) = (bounds.min, bounds.max);
    let pad = (hi - lo) * 0.1;
    (0..count)
        .map(|_| {
            let position = Vec3::new(
                rng.range(lo.x - pad.x, hi.x + pad.x),
                rng.range(lo.y - pad.y, hi.y + pad.y),
                rng.range(lo.z - pad.z, hi.z + pad.z),
            );
            let range = rng.range(min_radius, max_radius);
            let hue = rng.range(0.0, 1.0);
            SceneLight {
                kind: LightKind::Point,
                position,
                direction: Vec3::NEG_Z,
                color: hue_to_rgb(hue),
                intensity: range * range * 0.08,
                range: Some(range),
                casts_shadow: false,
            }
        })
        .collect()
}

/// Marks the `count` punctual lights that matter most to `camera` as shadow casters: those
/// whose influence (range sphere) covers the most of a `viewport_height`-pixel screen.
/// Directional lights and lights already casting are left as they are; returns how many
/// lights were marked (fewer than `count` when fewer are visible).
pub fn pick_shadowed(
    lights: &mut [SceneLight],
    camera: &FrameCamera,
    viewport_height: f32,
    count: usize,
) -> usize {
    let mut ranked: Vec<(f32, usize)> = lights
        .iter()
        .enumerate()
        .filter(|(_, l)| l.kind != LightKind::Directional && !l.casts_shadow)
        .filter_map(|(i, l)| {
            let radius = l.range?;
            let px = crate::shadow::resolution::projected_radius_px(
                l.position,
                radius,
                camera.view,
                camera.projection,
                viewport_height,
            );
            (px > 0.0).then_some((px, i))
        })
        .collect();
    ranked.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    for &(_, i) in ranked.iter().take(count) {
        lights[i].casts_shadow = true;
    }
    ranked.len().min(count)
}

/// The instance tools move to exercise dynamic shadows: the scene's last sphere (the built-in
/// courtyard has several), else its last instance; `None` for a scene without instances.
pub fn moving_instance(scene: &Scene) -> Option<usize> {
    scene
        .instances
        .iter()
        .rposition(|i| scene.meshes[i.mesh].name.starts_with("sphere"))
        .or_else(|| scene.instances.len().checked_sub(1))
}

/// A saturated colour around the hue wheel.
fn hue_to_rgb(h: f32) -> Vec3 {
    let k = |n: f32| {
        let x = (n + h * 6.0) % 6.0;
        1.0 - (x.min(4.0 - x).clamp(0.0, 1.0))
    };
    Vec3::new(k(5.0), k(3.0), k(1.0)) * 0.8 + Vec3::splat(0.2)
}
