//! The frame's lights on the GPU: punctual lights (culled into lists, in item order) and
//! directional lights (never culled), with the bounding spheres culling tests.

use crate::frame_data::InputError;
use glam::Vec3;
use shaders_gen::forward::forward;
use shaders_gen::shared::light_set;
use shaders_gen::shared::shadow_atlas::NO_SHADOW;
use wgpu::util::DeviceExt as _;

use crate::culling::LightSphere;
use crate::scene::{LightKind, SceneLight};

/// Range standing in for "infinite" in culling spheres.
const INFINITE_RANGE: f32 = 1.0e30;

/// The largest of `2x² − x⁶` over `x` in `[0, 1]` (at `x⁴ = 2/3`): what the range window takes
/// from a light's `intensity / d²` at `d = x · range`, in units of `intensity / range²`.
const WINDOW_LOSS_MAX: f32 = 1.088_662;

/// The range that cuts a light without one off at illuminance `cutoff` (before exposure): the
/// range window `(1 − (d/r)⁴)²` takes `(2(d/r)⁴ − (d/r)⁸) · I / d²` from the light's
/// illuminance `I / d²` (`I` its intensity times its brightest colour channel), at most
/// [`WINDOW_LOSS_MAX`]` · I / r²`; so `r = sqrt(WINDOW_LOSS_MAX · I / cutoff)` (at least
/// `1e-4`) changes no surface's illuminance by more than `cutoff`. `None` for `cutoff <= 0`
/// (the light stays infinite).
pub fn effective_range(light: &SceneLight, cutoff: f32) -> Option<f32> {
    let brightest = light.color.max_element().max(0.0);
    let intensity = light.intensity.max(0.0) * brightest;
    (cutoff > 0.0).then(|| (WINDOW_LOSS_MAX * intensity / cutoff).sqrt().max(1.0e-4))
}

/// `lights` with every point and spot light that has no range given its
/// [`effective_range`] for illuminance `cutoff`.
pub fn with_effective_ranges(lights: &[SceneLight], cutoff: f32) -> Vec<SceneLight> {
    lights
        .iter()
        .map(|l| {
            let mut l = *l;
            if l.kind != LightKind::Directional && l.range.is_none() {
                l.range = effective_range(&l, cutoff);
            }
            l
        })
        .collect()
}

/// The lights of a frame: storage buffers the shading passes bind and the culling spheres.
#[derive(Debug, Clone)]
pub struct LightSet {
    /// Point and spot lights, in culling item order.
    pub punctual: Vec<forward::GpuLight>,
    pub directional: Vec<forward::GpuLight>,
    /// One bounding sphere per punctual light, in the same order.
    pub spheres: Vec<LightSphere>,
    /// The scene lights behind `punctual` and `directional`, in their orders (what the shadow
    /// pass needs: `casts_shadow`, cone angles, infinite ranges).
    pub punctual_sources: Vec<SceneLight>,
    pub directional_sources: Vec<SceneLight>,
    /// `punctual` on the GPU (one placeholder element when empty).
    pub punctual_buffer: wgpu::Buffer,
    /// `directional` on the GPU (one placeholder element when empty).
    pub directional_buffer: wgpu::Buffer,
}

impl LightSet {
    /// The `light_set` library's part of every lit pass's group 0 (its generated builder): the
    /// punctual and directional light records.
    pub fn bindings(&self) -> light_set::Group0<'_> {
        light_set::Group0 {
            lights: self.punctual_buffer.as_entire_buffer_binding(),
            directional: self.directional_buffer.as_entire_buffer_binding(),
        }
    }

    /// The most lights `device` can hold in one binding: the light records (the largest per-light
    /// buffer a pass binds) must fit the storage-binding and buffer size limits.
    pub fn max_lights(device: &wgpu::Device) -> usize {
        crate::gpu::requirements::storage_binding_records(device, size_of::<forward::GpuLight>())
            as usize
    }

    /// [`LightSet::new`], or [`InputError::TooManyLights`](crate::frame::InputError::TooManyLights) past [`LightSet::max_lights`];
    /// with `previous`, the lights are written into its buffers where they fit (no new buffer:
    /// an engine that moves its lights every frame re-uploads them in place), else into new
    /// ones.
    pub fn checked(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        lights: &[SceneLight],
        previous: Option<&LightSet>,
    ) -> Result<Self, super::RenderError> {
        let max = Self::max_lights(device);
        if lights.len() > max {
            return Err(super::RenderError::Input(InputError::TooManyLights {
                count: lights.len(),
                max,
            }));
        }
        let c = Converted::new(lights);
        let store = |label: &str, records: &[forward::GpuLight], old: Option<&wgpu::Buffer>| {
            let records = with_placeholder(records);
            let bytes: &[u8] = bytemuck::cast_slice(records);
            match old {
                Some(old) if old.size() >= bytes.len() as u64 => {
                    queue.write_buffer(old, 0, bytes);
                    old.clone()
                }
                _ => light_storage(device, label, records),
            }
        };
        let punctual = store("lights", &c.punctual, previous.map(|p| &p.punctual_buffer));
        let directional = store(
            "directional lights",
            &c.directional,
            previous.map(|p| &p.directional_buffer),
        );
        Ok(c.into_set(punctual, directional))
    }

    /// Converts scene lights (and any procedural ones) and uploads them.
    pub fn new(device: &wgpu::Device, lights: &[SceneLight]) -> Self {
        let c = Converted::new(lights);
        let punctual = light_storage(device, "lights", with_placeholder(&c.punctual));
        let directional = light_storage(
            device,
            "directional lights",
            with_placeholder(&c.directional),
        );
        c.into_set(punctual, directional)
    }
}

/// A [`LightSet`] before its buffers.
struct Converted {
    punctual: Vec<forward::GpuLight>,
    directional: Vec<forward::GpuLight>,
    spheres: Vec<LightSphere>,
    punctual_sources: Vec<SceneLight>,
    directional_sources: Vec<SceneLight>,
}

impl Converted {
    fn new(lights: &[SceneLight]) -> Self {
        let mut punctual = Vec::new();
        let mut directional = Vec::new();
        let mut spheres = Vec::new();
        let (mut punctual_sources, mut directional_sources) = (Vec::new(), Vec::new());
        for l in lights {
            let gpu_light = gpu_light(l);
            if l.kind == LightKind::Directional {
                directional.push(gpu_light);
                directional_sources.push(*l);
                continue;
            }
            punctual_sources.push(*l);
            let reach = l.range.unwrap_or(INFINITE_RANGE);
            spheres.push(match l.kind {
                LightKind::Spot { outer_cone, .. } => {
                    LightSphere::spot(l.position, l.direction, outer_cone.cos(), reach)
                }
                _ => LightSphere {
                    center: l.position,
                    radius: reach,
                },
            });
            punctual.push(gpu_light);
        }
        Self {
            punctual,
            directional,
            spheres,
            punctual_sources,
            directional_sources,
        }
    }

    fn into_set(self, punctual_buffer: wgpu::Buffer, directional_buffer: wgpu::Buffer) -> LightSet {
        LightSet {
            punctual: self.punctual,
            directional: self.directional,
            spheres: self.spheres,
            punctual_sources: self.punctual_sources,
            directional_sources: self.directional_sources,
            punctual_buffer,
            directional_buffer,
        }
    }
}

fn gpu_light(l: &SceneLight) -> forward::GpuLight {
    let (kind, cos_inner, cos_outer) = match l.kind {
        LightKind::Point => (forward::KIND_POINT, 1.0, 1.0),
        LightKind::Spot {
            inner_cone,
            outer_cone,
        } => (forward::KIND_SPOT, inner_cone.cos(), outer_cone.cos()),
        LightKind::Directional => (forward::KIND_DIRECTIONAL, 1.0, 1.0),
    };
    forward::GpuLight::new(
        l.position,
        l.range.unwrap_or(0.0),
        l.color,
        l.intensity,
        l.direction,
        kind,
        cos_inner,
        cos_outer,
        NO_SHADOW,
    )
}

/// `lights`, or one placeholder record when there is none (a binding is never empty).
fn with_placeholder(lights: &[forward::GpuLight]) -> &[forward::GpuLight] {
    static PLACEHOLDER: std::sync::LazyLock<[forward::GpuLight; 1]> =
        std::sync::LazyLock::new(|| {
            [forward::GpuLight::new(
                Vec3::ZERO,
                0.0,
                Vec3::ZERO,
                0.0,
                Vec3::Z,
                0,
                1.0,
                1.0,
                NO_SHADOW,
            )]
        });
    if lights.is_empty() {
        &*PLACEHOLDER
    } else {
        lights
    }
}

/// A storage buffer holding `records`.
fn light_storage(
    device: &wgpu::Device,
    label: &str,
    records: &[forward::GpuLight],
) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(records),
        // COPY_DST: the shadow pass writes each light's `shadow` index as its atlas changes,
        // and new lights are written in place; COPY_SRC: tools and tests read the records back
        // as the kernels see them.
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(intensity: f32, color: Vec3, range: Option<f32>) -> SceneLight {
        SceneLight {
            kind: LightKind::Point,
            position: Vec3::ZERO,
            direction: Vec3::NEG_Z,
            color,
            intensity,
            range,
            casts_shadow: false,
        }
    }

    #[test]
    fn the_effective_range_window_takes_at_most_the_cutoff() {
        let light = point(180.0, Vec3::new(1.0, 0.63, 0.5), None);
        let cutoff = 1.0e-3;
        let r = effective_range(&light, cutoff).expect("finite");
        let at_range = light.intensity * light.color.max_element() / (r * r);
        assert!(at_range < cutoff, "{at_range} at the range");
        // What the range window takes away, anywhere inside it, stays within the cutoff.
        let worst = (1..=10_000)
            .map(|i| {
                let d = r * i as f32 / 10_000.0;
                let x = (d / r).powi(4);
                let window = (1.0 - x).clamp(0.0, 1.0).powi(2);
                light.intensity * light.color.max_element() * (1.0 - window) / (d * d)
            })
            .fold(0.0f32, f32::max);
        assert!(worst <= cutoff * 1.000_01, "window removes up to {worst}");
        assert!(worst >= cutoff * 0.999, "the bound is tight: {worst}");
        assert_eq!(effective_range(&light, 0.0), None, "0 keeps it infinite");
        let dark = point(0.0, Vec3::ONE, None);
        assert!(effective_range(&dark, cutoff).is_some_and(|r| r > 0.0));
    }

    #[test]
    fn only_range_less_punctual_lights_get_a_range() {
        let mut sun = point(3.0, Vec3::ONE, None);
        sun.kind = LightKind::Directional;
        let lights = [
            point(10.0, Vec3::ONE, None),
            point(10.0, Vec3::ONE, Some(2.5)),
            sun,
        ];
        let bounded = with_effective_ranges(&lights, 1.0e-3);
        assert_eq!(bounded[0].range, effective_range(&lights[0], 1.0e-3));
        assert_eq!(bounded[1].range, Some(2.5));
        assert_eq!(bounded[2].range, None);
        assert_eq!(with_effective_ranges(&lights, 0.0)[0].range, None);
    }
}
