//! The vocabulary light culling speaks, on the CPU and in the renderer alike: a camera as
//! culling sees it, light bounding spheres (with the spot cone's closed form), the froxel grid,
//! the culling methods and how they number their cells, and planes. Production code and the
//! independent CPU reference (the sibling module `reference`) both use these types; its tests
//! and culling functions are its own.

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

/// Number of depth cells in a 2.5D tile mask.
#[cfg(any(test, feature = "internals"))]
pub const DEPTH_MASK_CELLS: u32 = 32;
/// Edge of a super-tile in pixels.
#[cfg(any(test, feature = "internals"))]
pub const SUPER_TILE_PIXELS: u32 = 128;

/// A froxel grid: the screen tiles of `tile`×`tile` pixels × `slices` exponential depth slices
/// between `near` and `far` (view depth). Samples nearer than `near` fall in slice 0, farther
/// than `far` in slice `slices − 1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClusterGrid {
    pub tile: u32,
    pub slices: u32,
    pub near: f32,
    pub far: f32,
}

impl ClusterGrid {
    /// The depth slice of view depth `d`.
    pub fn slice(&self, d: f32) -> u32 {
        let t = (d / self.near).ln() / (self.far / self.near).ln();
        ((t * self.slices as f32).floor().max(0.0) as u32).min(self.slices - 1)
    }

    /// View depth where slice `k` starts (slice 0 starts at 0; slice `slices` means infinity).
    pub fn slice_start(&self, k: u32) -> f32 {
        match k {
            0 => 0.0,
            k if k >= self.slices => f32::INFINITY,
            k => self.near * (self.far / self.near).powf(k as f32 / self.slices as f32),
        }
    }
}

/// A culling method and its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// One frustum per `tile`×`tile` pixel tile, bounded by the tile's depth range (and, without
    /// MSAA, by the view-space box of that frustum). With
    /// `transparent`, a second list per tile (cells `tiles..2·tiles`) for blended surfaces,
    /// from the near plane to the tile's farthest sample (the far plane when any of its samples
    /// is sky).
    Tiled { tile: u32, transparent: bool },
    /// Tiled, plus a 32-cell depth mask per tile from the geometry, ANDed with each light's
    /// (opaque lists only).
    Depth25 { tile: u32, transparent: bool },
    /// One frustum per froxel (without MSAA narrowed by the froxel's view-space bounding box).
    /// With `skip_empty`, froxels holding no depth sample get no lights, and the others are
    /// clipped to their tile's sample depth range.
    Clustered { grid: ClusterGrid, skip_empty: bool },
}

impl Method {
    /// Tiled without transparent lists.
    pub fn tiled(tile: u32) -> Self {
        Self::Tiled {
            tile,
            transparent: false,
        }
    }

    /// 2.5D without transparent lists.
    pub fn depth25(tile: u32) -> Self {
        Self::Depth25 {
            tile,
            transparent: false,
        }
    }

    /// Whether the method writes a second, transparent list per tile (tiled and 2.5D with
    /// blended surfaces).
    pub fn transparent_lists(&self) -> bool {
        matches!(
            *self,
            Self::Tiled {
                transparent: true,
                ..
            } | Self::Depth25 {
                transparent: true,
                ..
            }
        )
    }

    /// Tile edge in pixels.
    pub fn tile(&self) -> u32 {
        match *self {
            Self::Tiled { tile, .. } | Self::Depth25 { tile, .. } => tile,
            Self::Clustered { grid, .. } => grid.tile,
        }
    }

    /// Cell grid dimensions `[tiles x, tiles y, lists per tile]` for a `width`×`height` target.
    pub fn dims(&self, width: u32, height: u32) -> [u32; 3] {
        let t = self.tile();
        let lists = match *self {
            Self::Tiled { transparent, .. } | Self::Depth25 { transparent, .. } => {
                1 + u32::from(transparent)
            }
            Self::Clustered { grid, .. } => grid.slices,
        };
        [width.div_ceil(t), height.div_ceil(t), lists]
    }

    /// The cell holding the (opaque) sample at pixel `(x, y)` with view depth `view_depth`.
    pub fn cell_of(&self, width: u32, height: u32, x: u32, y: u32, view_depth: f32) -> usize {
        let [dx, dy, _] = self.dims(width, height);
        let t = self.tile();
        let tile = (y / t) * dx + x / t;
        match *self {
            Self::Tiled { .. } | Self::Depth25 { .. } => tile as usize,
            Self::Clustered { grid, .. } => (grid.slice(view_depth) * dx * dy + tile) as usize,
        }
    }
}

/// A plane `n · p + d = 0` with unit `n` pointing into the kept half-space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    pub normal: Vec3,
    pub d: f32,
}

impl Plane {
    /// The plane `v.xyz · p + v.w = 0`, normalised.
    pub fn from_vec4(v: Vec4) -> Self {
        let len = v.truncate().length();
        Self {
            normal: v.truncate() / len,
            d: v.w / len,
        }
    }

    /// Signed distance of `p` (positive inside).
    pub fn distance(&self, p: Vec3) -> f32 {
        self.normal.dot(p) + self.d
    }

    /// The near plane at view depth `depth` (keeps points at least that far).
    pub fn near(depth: f32) -> Self {
        Self {
            normal: Vec3::NEG_Z,
            d: -depth,
        }
    }

    /// The far plane at view depth `depth` (keeps points at most that far).
    pub fn far(depth: f32) -> Self {
        Self {
            normal: Vec3::Z,
            d: depth,
        }
    }
}
