//! What bounds one cell: its side and depth planes, the view-space box of its frustum, the
//! depth range and 2.5D mask of its surface samples, and the surface samples themselves.

use glam::Vec3;

use super::Plane;
use super::frustum::tile_side_planes;
use super::{ClusterGrid, DEPTH_MASK_CELLS};
use super::{CullCamera, DepthBuffer};
use crate::decals::OrientedBox;

/// Whether any sample of the square cell `(i, j)` of `size` pixels (inside the screen) is sky.
pub(super) fn has_sky(depth: &DepthBuffer, size: u32, i: u32, j: u32) -> bool {
    let xs = (i * size)..((i + 1) * size).min(depth.width);
    xs.flat_map(|x| {
        ((j * size)..((j + 1) * size).min(depth.height))
            .flat_map(move |y| (0..depth.samples).map(move |s| (x, y, s)))
    })
    .any(|(x, y, s)| !DepthBuffer::is_surface(depth.get(x, y, s)))
}

/// View depths of the near and far planes (wgpu depth 0 and 1).
pub(super) fn camera_range(camera: &CullCamera) -> (f32, f32) {
    (
        -camera.unproject(0.0, 0.0, 0.0).z,
        -camera.unproject(0.0, 0.0, 1.0).z,
    )
}

/// The four side planes of the square cell `(i, j)` of `size` pixels (not clamped to the
/// screen).
pub(super) fn side_planes(camera: &CullCamera, size: u32, i: u32, j: u32) -> [Plane; 4] {
    let (x0, y1) = camera.pixel_to_ndc((i * size) as f32, (j * size) as f32);
    let (x1, y0) = camera.pixel_to_ndc(((i + 1) * size) as f32, ((j + 1) * size) as f32);
    tile_side_planes(camera.projection, x0, x1, y0, y1)
}

pub(super) fn with_depth(sides: [Plane; 4], near: f32, far: f32) -> [Plane; 6] {
    let [l, r, b, t] = sides;
    [l, r, b, t, Plane::near(near), Plane::far(far)]
}

/// The view-space bounding box of a froxel: tile `(i, j)` between view depths `zn` and `zf`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct FroxelBox {
    min: Vec3,
    max: Vec3,
}

pub(super) fn froxel_box(
    camera: &CullCamera,
    tile: u32,
    i: u32,
    j: u32,
    zn: f32,
    zf: f32,
) -> FroxelBox {
    let mut b = FroxelBox {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };
    for (px, py) in [(i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)] {
        let (nx, ny) = camera.pixel_to_ndc((px * tile) as f32, (py * tile) as f32);
        for z in [zn, zf] {
            let p = corner_at(camera, nx, ny, z);
            b.min = b.min.min(p);
            b.max = b.max.max(p);
        }
    }
    b
}

/// The view-space point at view depth `z` on the line of points that project to NDC
/// `(nx, ny)`.
fn corner_at(camera: &CullCamera, nx: f32, ny: f32, z: f32) -> Vec3 {
    if camera.is_orthographic() {
        // The line runs from the near plane's point to the far plane's: interpolate by depth
        // (both points share x and y, but nothing here relies on it).
        let (a, b) = (camera.unproject(nx, ny, 0.0), camera.unproject(nx, ny, 1.0));
        let t = (z + a.z) / (a.z - b.z);
        return a + (b - a) * t;
    }
    // Perspective: the corner's ray through the eye, scaled to view depth 1, then to `z`.
    let p = camera.unproject(nx, ny, 0.5);
    p / -p.z * z
}

impl FroxelBox {
    /// Distance from `p` to the box (0 inside).
    pub(super) fn distance(&self, p: Vec3) -> f32 {
        p.distance(p.clamp(self.min, self.max))
    }

    /// How far the oriented box's axis-aligned bounds reach into this box along the axis where
    /// they overlap least (negative: the gap where they miss).
    pub(super) fn box_margin(&self, b: &OrientedBox) -> f32 {
        let extent = Vec3::new(
            b.radius_along(Vec3::X),
            b.radius_along(Vec3::Y),
            b.radius_along(Vec3::Z),
        );
        let gap = (self.min - (b.center + extent)).max((b.center - extent) - self.max);
        -gap.max_element()
    }
}

/// The smallest margin by which an oriented box clears the planes: `min(n · c + d + r_n)` with
/// `r_n` the box's extent along `n`; negative when some plane has every corner behind it.
pub(super) fn box_margin(planes: &[Plane], b: &OrientedBox) -> f32 {
    planes
        .iter()
        .map(|p| p.distance(b.center) + b.radius_along(p.normal))
        .fold(f32::INFINITY, f32::min)
}

/// Calls `f(x, y, view_position)` for every sample that holds a surface.
pub fn for_each_surface_sample(
    camera: &CullCamera,
    depth: &DepthBuffer,
    mut f: impl FnMut(u32, u32, Vec3),
) {
    for y in 0..depth.height {
        for x in 0..depth.width {
            for s in 0..depth.samples {
                let z = depth.get(x, y, s);
                if DepthBuffer::is_surface(z) {
                    let (ox, oy) = depth.sample_offset(s);
                    let (nx, ny) = camera.pixel_to_ndc(x as f32 + ox, y as f32 + oy);
                    f(x, y, camera.unproject(nx, ny, z));
                }
            }
        }
    }
}

/// A tile's view-depth range over its surface samples, its 2.5D geometry mask and the samples'
/// view depths.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct TileDepth {
    pub(super) min: f32,
    pub(super) max: f32,
    geometry_mask: u32,
    depths: Vec<f32>,
}

impl TileDepth {
    pub(super) fn gather(
        camera: &CullCamera,
        depth: &DepthBuffer,
        tile: u32,
        i: u32,
        j: u32,
    ) -> Option<Self> {
        let mut depths = Vec::new();
        for y in (j * tile)..((j + 1) * tile).min(depth.height) {
            for x in (i * tile)..((i + 1) * tile).min(depth.width) {
                for s in 0..depth.samples {
                    let z = depth.get(x, y, s);
                    if DepthBuffer::is_surface(z) {
                        // View depth of the sample; x/y do not change view z.
                        depths.push(-camera.unproject(0.0, 0.0, z).z);
                    }
                }
            }
        }
        let min = depths.iter().copied().fold(f32::INFINITY, f32::min);
        let max = depths.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        if depths.is_empty() {
            return None;
        }
        let mut tile = Self {
            min,
            max,
            geometry_mask: 0,
            depths: Vec::new(),
        };
        for &d in &depths {
            tile.geometry_mask |= 1 << tile.cell(d);
        }
        tile.depths = depths;
        Some(tile)
    }

    /// The depth slices of `grid` holding a sample (bit `k` for slice `k`).
    pub(super) fn slices(&self, grid: ClusterGrid) -> u32 {
        self.depths
            .iter()
            .fold(0, |bits, &d| bits | 1 << grid.slice(d))
    }

    /// The mask cell of view depth `d`, clamped to the tile's range.
    fn cell(&self, d: f32) -> u32 {
        let span = self.max - self.min;
        if span <= 0.0 {
            return 0;
        }
        let t = (d - self.min) / span * DEPTH_MASK_CELLS as f32;
        (t.floor().max(0.0) as u32).min(DEPTH_MASK_CELLS - 1)
    }

    /// Whether a light spanning view depths `[lo, hi]` shares a cell with the geometry.
    pub(super) fn overlaps(&self, lo: f32, hi: f32) -> bool {
        if hi < self.min || lo > self.max || lo > hi {
            return false;
        }
        let (a, b) = (self.cell(lo), self.cell(hi));
        let light_mask = if b - a >= 31 {
            u32::MAX
        } else {
            ((1u32 << (b - a + 1)) - 1) << a
        };
        self.geometry_mask & light_mask != 0
    }
}
