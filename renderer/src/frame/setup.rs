//! Frame set-up helpers for tools and tests: the camera a scene opens on (its own, or one that
//! frames it), seeded procedural lights, and the built-in courtyard's look.

use glam::{Mat4, Vec3, camera::rh};

use super::{FrameCamera, RendererConfig};
use crate::scene::{Aabb, CameraProjection, LightKind, Scene, SceneLight};

/// A tiny deterministic generator (SplitMix64), so seeded scenes never change between runs.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

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

/// A perspective camera looking at the centre of `bounds` from the front and a little above.
pub fn framing_camera(bounds: Aabb, aspect: f32) -> FrameCamera {
    let center = bounds.center();
    let radius = ((bounds.max - bounds.min).length() * 0.5).max(1e-3);
    let eye = center + Vec3::new(0.0, 0.35, 1.0).normalize() * radius * 2.4;
    FrameCamera::look_at(
        eye,
        center,
        Vec3::Y,
        FRAMING_YFOV_DEGREES.to_radians(),
        aspect,
        (radius * 0.05, radius * 8.0),
    )
}

/// The field of view of [`framing_camera`].
pub const FRAMING_YFOV_DEGREES: f32 = 45.0;

/// The scene's camera `index`: a perspective camera at the viewport's `aspect` (its far plane,
/// or ten scene sizes where the file sets none), an orthographic one with the file's `xmag` and
/// `ymag` as they are (glTF's orthographic matrix: a viewport of another aspect stretches it).
pub fn camera_of(scene: &Scene, index: usize, aspect: f32) -> Option<FrameCamera> {
    let size = (scene.bounds.max - scene.bounds.min).length().max(1e-3);
    scene.cameras.get(index).map(|c| match c.projection {
        CameraProjection::Perspective {
            yfov, znear, zfar, ..
        } => scene_camera(
            c.world_from_view,
            yfov,
            aspect,
            znear,
            zfar.unwrap_or(size * 10.0),
        ),
        CameraProjection::Orthographic {
            xmag,
            ymag,
            znear,
            zfar,
        } => FrameCamera::orthographic(c.world_from_view, (xmag, ymag), (znear, zfar)),
    })
}

/// The scene's first camera, else [`framing_camera`]: what tools open a scene on.
pub fn default_camera(scene: &Scene, aspect: f32) -> FrameCamera {
    camera_of(scene, 0, aspect).unwrap_or_else(|| framing_camera(scene.bounds, aspect))
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

/// A perspective camera placed by `world_from_view` (a glTF node's transform), with vertical
/// field of view `yfov`.
pub fn scene_camera(
    world_from_view: Mat4,
    yfov: f32,
    aspect: f32,
    near: f32,
    far: f32,
) -> FrameCamera {
    FrameCamera {
        view: world_from_view.inverse(),
        projection: rh::proj::directx::perspective(yfov, aspect, near, far),
        eye: world_from_view.transform_point3(Vec3::ZERO),
        near,
        far,
        orthographic: false,
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

/// A texture the renderer can draw a frame into (`config.output_format`, the configured size),
/// readable back with [`crate::readback::read_texture_rgba8`].
pub fn create_target(device: &wgpu::Device, config: &RendererConfig) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("frame target"),
        size: wgpu::Extent3d {
            width: config.width,
            height: config.height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: config.output_format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}
