//! Independent CPU reference for light culling, written from the literature (Harada's Forward+,
//! the tiled/2.5D tutorial in reference 000, Olsson's clustered shading), not from the kernels.
//!
//! Conventions shared with the GPU kernels:
//! - right-handed view space, camera looking down −Z; "view depth" is `-z`;
//! - wgpu depth: 0 at the near plane, 1 at the far plane; a sample with depth 1 is sky and
//!   belongs to no surface;
//! - pixel `(x, y)` has NDC `x = 2 (x / w) − 1`, `y = 1 − 2 (y / h)`; tile `(i, j)` of size `t`
//!   spans pixels `[i t, (i + 1) t)` without clamping to the screen edge;
//! - every light is a sphere in view space (spot lights use their cone's bounding sphere); every
//!   decal an oriented box in view space.
//!
//! [`cull`] gives each tile or cluster its sorted list of lights that pass the method's test,
//! plus the lights whose test was too close to call in `f32` (see [`Borderline`]).
//! [`exact`] gives, per sample, the lights whose sphere really contains the sample's surface
//! point, and [`exact::cull_efficiency`] compares the two. [`cull_boxes`] does the same for
//! decal boxes; a box that contains a sample's point must be in the sample's cell.
//! [`cone`] finds a spot light's bounding sphere its own way, from the sector the light
//! reaches, to check the renderer's closed form ([`LightSphere::spot`]).

mod cell_bounds;
mod cells;
pub mod cone;
mod depth;
pub mod exact;
mod frustum;
mod methods;
#[cfg(test)]
mod ortho_tests;

pub use cells::{Borderline, CellLists, ClusterGrid, Method, SUPER_TILE_PIXELS};
pub use depth::{DepthBuffer, standard_sample_offset};
pub use frustum::{Plane, tile_side_planes};
pub use methods::{cull, cull_boxes, cull_brute_force};

use glam::{Mat4, Vec3, Vec4};

/// A camera as culling sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CullCamera {
    pub view: Mat4,
    pub projection: Mat4,
    pub width: u32,
    pub height: u32,
}

impl CullCamera {
    /// View-space position of the surface at NDC `(x, y)` and wgpu depth `depth`.
    pub fn unproject(&self, ndc_x: f32, ndc_y: f32, depth: f32) -> Vec3 {
        let p = self.projection.inverse() * Vec4::new(ndc_x, ndc_y, depth, 1.0);
        p.truncate() / p.w
    }

    /// Whether the projection is orthographic: clip `w` is 1 for every point (its last row is
    /// `(0, 0, 0, 1)`), so screen position does not depend on depth.
    pub fn is_orthographic(&self) -> bool {
        self.projection.row(3) == Vec4::W
    }

    /// NDC of a point in pixel coordinates (pixel corners at integers).
    pub fn pixel_to_ndc(&self, px: f32, py: f32) -> (f32, f32) {
        (
            2.0 * px / self.width as f32 - 1.0,
            1.0 - 2.0 * py / self.height as f32,
        )
    }
}

/// A light's bounding sphere in world space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightSphere {
    pub center: Vec3,
    pub radius: f32,
}

impl LightSphere {
    /// The smallest sphere around a spot light's cone: apex `position`, unit `direction`,
    /// half-angle with cosine `cos_outer`, reaching `range`.
    pub fn spot(position: Vec3, direction: Vec3, cos_outer: f32, range: f32) -> Self {
        let cos = cos_outer.clamp(0.0, 1.0);
        let sin = (1.0 - cos * cos).sqrt();
        if cos <= std::f32::consts::FRAC_1_SQRT_2 {
            // Wide cone (over 45°): the sphere through the cap's rim, centred on the cap's plane.
            Self {
                center: position + direction * (range * cos),
                radius: range * sin,
            }
        } else {
            // Narrow cone: the sphere through the apex and the rim.
            let r = range / (2.0 * cos);
            Self {
                center: position + direction * r,
                radius: r,
            }
        }
    }

    /// The sphere in view space.
    pub fn to_view(self, view: Mat4) -> Self {
        Self {
            center: view.transform_point3(self.center),
            radius: self.radius,
        }
    }
}
