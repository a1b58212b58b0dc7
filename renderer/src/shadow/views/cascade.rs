//! The four stable orthographic cascades of the directional light: practical splits of the
//! camera's view depth, each fitted with its slice's bounding sphere and snapped to whole
//! texels in light space.

use glam::{Mat4, Vec3};

use super::{LightView, look_along, reversed_orthographic};
use crate::scene::Aabb;

/// Number of directional cascades.
pub const CASCADE_COUNT: usize = 4;

/// Weight of the logarithmic split against the uniform one in [`cascade_splits`].
pub const CASCADE_SPLIT_LAMBDA: f32 = 0.75;

/// The far view depth of each cascade over `[near, distance]`: the practical split, `λ` =
/// [`CASCADE_SPLIT_LAMBDA`] of the logarithmic split plus `1 − λ` of the uniform one. The last
/// is exactly `distance`. `near` is clamped to at least 1e-4 and `distance` to more than `near`.
pub fn cascade_splits(near: f32, distance: f32) -> [f32; CASCADE_COUNT] {
    let near = near.max(1e-4);
    let distance = distance.max(near * 1.001);
    std::array::from_fn(|i| {
        if i + 1 == CASCADE_COUNT {
            return distance;
        }
        let t = (i + 1) as f32 / CASCADE_COUNT as f32;
        let log = near * (distance / near).powf(t);
        let uniform = near + (distance - near) * t;
        CASCADE_SPLIT_LAMBDA * log + (1.0 - CASCADE_SPLIT_LAMBDA) * uniform
    })
}

/// The bounding sphere of the camera frustum slice between view depths `near` and `far`, whose
/// corners lie at `(±tan_x d, ±tan_y d, −d)`: its centre's view depth and its radius. It is
/// centred on the view axis, so it depends on the slice only, not on the camera's orientation.
pub fn slice_bounding_sphere(tan_x: f32, tan_y: f32, near: f32, far: f32) -> (f32, f32) {
    let k2 = tan_x * tan_x + tan_y * tan_y;
    // Equidistant from the near and far corners, unless that lies beyond the far plane.
    let center = ((far + near) * (1.0 + k2) * 0.5).min(far);
    let to_near = ((center - near).powi(2) + near * near * k2).sqrt();
    let to_far = ((far - center).powi(2) + far * far * k2).sqrt();
    (center, to_near.max(to_far))
}

/// How the camera's frustum widens with view depth: a perspective camera's slice at depth `d`
/// spans `±tan_x d` by `±tan_y d`; an orthographic one's spans `±half_width` by `±half_height`
/// at every depth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CameraLens {
    Perspective { tan_x: f32, tan_y: f32 },
    Orthographic { half_width: f32, half_height: f32 },
}

impl CameraLens {
    /// A perspective lens of vertical field of view `fovy` (radians, clamped inside
    /// `(0, π)`) and `aspect` width / height.
    pub fn perspective(fovy: f32, aspect: f32) -> Self {
        let tan_y = (fovy.clamp(1e-3, std::f32::consts::PI - 1e-3) * 0.5).tan();
        Self::Perspective {
            tan_x: tan_y * aspect.max(1e-3),
            tan_y,
        }
    }

    /// The lens of a wgpu projection: orthographic when its last row is `(0, 0, 0, 1)`.
    pub fn of(projection: Mat4) -> Self {
        if projection.row(3) == glam::Vec4::W {
            // x_ndc = x_view · m00 + offset: the half extents are 1 / m00 and 1 / m11.
            return Self::Orthographic {
                half_width: 1.0 / projection.x_axis.x,
                half_height: 1.0 / projection.y_axis.y,
            };
        }
        Self::perspective(
            crate::shadow::resolution::projection_fovy(projection),
            projection.y_axis.y / projection.x_axis.x,
        )
    }

    /// The bounding sphere of the frustum slice between view depths `near` and `far`: its
    /// centre's view depth and its radius (centred on the view axis).
    pub fn slice_sphere(&self, near: f32, far: f32) -> (f32, f32) {
        match *self {
            Self::Perspective { tan_x, tan_y } => slice_bounding_sphere(tan_x, tan_y, near, far),
            Self::Orthographic {
                half_width,
                half_height,
            } => {
                // A box: its centre, and the distance to any of its corners.
                let half_depth = (far - near) * 0.5;
                let radius =
                    (half_depth * half_depth + half_width * half_width + half_height * half_height)
                        .sqrt();
                (near + half_depth, radius)
            }
        }
    }
}

/// Four cascades of a directional light over the camera's view depth [near, distance], split
/// practically (lambda = 0.75 between log and uniform, [`cascade_splits`]), each fitted with a
/// bounding sphere of the split's frustum slice ([`slice_bounding_sphere`]: its size does not
/// change as the camera turns), an orthographic projection whose origin is snapped to whole
/// texels in light space (stable: moving the camera by less than a texel does not shift the
/// texel grid relative to the world), and a depth range extended towards the light to include
/// every caster of `scene_bounds`.
///
/// `camera_world_from_view` must be rigid (the inverse of the camera's view matrix); `lens` how
/// its frustum widens (perspective or orthographic). The region is one texel wider than the
/// sphere on each side, so snapping never pushes the slice out of it. Light space is a fixed
/// rotation of the world (it depends on `light_direction` only), with its origin at the world's.
pub fn cascade_views(
    camera_world_from_view: Mat4,
    lens: CameraLens,
    near: f32,
    distance: f32,
    light_direction: Vec3,
    side: u32,
    scene_bounds: &Aabb,
) -> [LightView; 4] {
    let light_from_world = look_along(Vec3::ZERO, light_direction);
    let near = near.max(1e-4);
    let splits = cascade_splits(near, distance);
    // The nearest caster's light-space z (the light looks down −z, so the largest z).
    let scene_light = scene_bounds.transformed(light_from_world);
    let caster_z =
        (!scene_light.is_empty() && scene_light.max.z.is_finite()).then_some(scene_light.max.z);
    std::array::from_fn(|i| {
        let slice_near = if i == 0 { near } else { splits[i - 1] };
        let (center_depth, radius) = lens.slice_sphere(slice_near, splits[i]);
        let center_world =
            camera_world_from_view.transform_point3(Vec3::new(0.0, 0.0, -center_depth));
        let sphere = Sphere {
            center: light_from_world.transform_point3(center_world),
            radius,
        };
        let mut view = cascade_view(sphere, side, caster_z);
        view.clip_from_world *= light_from_world;
        view.split_far = splits[i];
        view
    })
}

/// A sphere in light space.
#[derive(Debug, Clone, Copy)]
struct Sphere {
    center: Vec3,
    radius: f32,
}

/// The light-space (not yet world) view of one cascade: the sphere's square, one texel wider
/// on each side, its centre snapped to whole texels, depth from the nearer of the sphere and
/// the casters (`caster_z`) to the sphere's far side, padded by a texel.
fn cascade_view(sphere: Sphere, side: u32, caster_z: Option<f32>) -> LightView {
    let side = side.max(1) as f32;
    let half = sphere.radius / (1.0 - 2.0 / side).max(0.5);
    let texel = 2.0 * half / side;
    // Whole-texel centre: ndc = (x − k texel) / half = x / half − k (2 / side).
    let kx = (sphere.center.x / texel).round();
    let ky = (sphere.center.y / texel).round();
    let depth = -sphere.center.z;
    let mut near = depth - sphere.radius - texel;
    if let Some(z) = caster_z {
        near = near.min(-z - texel);
    }
    let far = depth + sphere.radius + texel;
    LightView {
        clip_from_world: reversed_orthographic(half, -kx * 2.0 / side, -ky * 2.0 / side, near, far),
        texel_world: texel,
        orthographic: true,
        split_far: 0.0,
    }
}
