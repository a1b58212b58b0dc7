//! The frame's lights on the GPU: punctual lights (culled into lists, in item order) and
//! directional lights (never culled), with the bounding spheres culling tests.

use glam::Vec3;
use shaders_gen::forward::forward;
use shaders_gen::shared::shadow_atlas::NO_SHADOW;
use wgpu::util::DeviceExt as _;

use crate::culling::reference::LightSphere;
use crate::scene::{LightKind, SceneLight};

/// Range standing in for "infinite" in culling spheres.
const INFINITE_RANGE: f32 = 1.0e30;

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
    /// The most lights `device` can hold in one binding: the light records (the largest per-light
    /// buffer a pass binds) must fit the storage-binding and buffer size limits.
    pub fn max_lights(device: &wgpu::Device) -> usize {
        crate::gpu::requirements::storage_binding_records(device, size_of::<forward::GpuLight>())
            as usize
    }

    /// [`LightSet::new`], or [`super::RenderError::TooManyLights`] past [`LightSet::max_lights`].
    pub fn checked(
        device: &wgpu::Device,
        lights: &[SceneLight],
    ) -> Result<Self, super::RenderError> {
        let max = Self::max_lights(device);
        if lights.len() > max {
            return Err(super::RenderError::TooManyLights {
                count: lights.len(),
                max,
            });
        }
        Ok(Self::new(device, lights))
    }

    /// Converts scene lights (and any procedural ones) and uploads them.
    pub fn new(device: &wgpu::Device, lights: &[SceneLight]) -> Self {
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
            punctual_buffer: light_storage(device, "lights", &punctual),
            directional_buffer: light_storage(device, "directional lights", &directional),
            punctual,
            directional,
            spheres,
            punctual_sources,
            directional_sources,
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

/// A storage buffer holding `lights` (at least one element, so the binding is never empty).
fn light_storage(device: &wgpu::Device, label: &str, lights: &[forward::GpuLight]) -> wgpu::Buffer {
    let placeholder = [forward::GpuLight::new(
        Vec3::ZERO,
        0.0,
        Vec3::ZERO,
        0.0,
        Vec3::Z,
        0,
        1.0,
        1.0,
        NO_SHADOW,
    )];
    let contents = if lights.is_empty() {
        &placeholder[..]
    } else {
        lights
    };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(contents),
        // COPY_DST: the shadow pass writes each light's `shadow` index as its atlas changes.
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
    })
}
