//! The three culling methods on the CPU: tiled, 2.5D (tiled with a 32-cell depth mask) and
//! clustered (froxels with exponential depth slices).

use glam::Vec3;

use super::frustum::{Plane, sphere_margin, tile_side_planes};
use super::{CullCamera, DepthBuffer, LightSphere};

/// Number of depth cells in a 2.5D tile mask.
pub const DEPTH_MASK_CELLS: u32 = 32;

/// A froxel grid: `x × y` screen tiles and `z` exponential depth slices between `near` and `far`
/// (view depth). Samples nearer than `near` fall in slice 0, farther than `far` in slice `z − 1`.
/// Column `i` spans pixels `[i·w/x, (i+1)·w/x)` in integer division (rows likewise), so a pixel's
/// samples all lie inside its froxel whatever the screen size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClusterGrid {
    pub x: u32,
    pub y: u32,
    pub z: u32,
    pub near: f32,
    pub far: f32,
}

impl ClusterGrid {
    /// The depth slice of view depth `d`.
    pub fn slice(&self, d: f32) -> u32 {
        let t = (d / self.near).ln() / (self.far / self.near).ln();
        ((t * self.z as f32).floor().max(0.0) as u32).min(self.z - 1)
    }

    /// The column (or row) holding pixel `p` when `count` columns share `size` pixels: the last
    /// `i` with `i·size/count ≤ p`.
    pub fn column_of(p: u32, count: u32, size: u32) -> u32 {
        ((p + 1) * count - 1) / size
    }

    /// First pixel of column (or row) `i`.
    pub fn column_start(i: u32, count: u32, size: u32) -> u32 {
        i * size / count
    }

    /// View depth where slice `k` starts (slice 0 starts at 0; slice `z` means infinity).
    pub fn slice_start(&self, k: u32) -> f32 {
        match k {
            0 => 0.0,
            k if k >= self.z => f32::INFINITY,
            k => self.near * (self.far / self.near).powf(k as f32 / self.z as f32),
        }
    }
}

/// A culling method and its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// One frustum per `tile`×`tile` pixel tile, bounded by the tile's depth range.
    Tiled { tile: u32 },
    /// Tiled, plus a 32-cell depth mask per tile from the geometry, ANDed with each light's.
    Depth25 { tile: u32 },
    /// One frustum per froxel. With `skip_empty`, froxels holding no depth sample get no lights.
    Clustered { grid: ClusterGrid, skip_empty: bool },
}

impl Method {
    /// Cell grid dimensions `[x, y, z]` for a `width`×`height` target.
    pub fn dims(&self, width: u32, height: u32) -> [u32; 3] {
        match *self {
            Self::Tiled { tile } | Self::Depth25 { tile } => {
                [width.div_ceil(tile), height.div_ceil(tile), 1]
            }
            Self::Clustered { grid, .. } => [grid.x, grid.y, grid.z],
        }
    }

    /// The cell holding the sample at pixel `(x, y)` with view depth `view_depth`.
    pub fn cell_of(&self, width: u32, height: u32, x: u32, y: u32, view_depth: f32) -> usize {
        let [dx, dy, _] = self.dims(width, height);
        match *self {
            Self::Tiled { tile } | Self::Depth25 { tile } => ((y / tile) * dx + x / tile) as usize,
            Self::Clustered { grid, .. } => {
                let i = ClusterGrid::column_of(x, grid.x, width);
                let j = ClusterGrid::column_of(y, grid.y, height);
                ((grid.slice(view_depth) * dy + j) * dx + i) as usize
            }
        }
    }
}

/// A light whose test result was within the `f32` tolerance: a GPU may decide either way.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Borderline {
    pub light: u32,
    /// The margin of the sphere test (see [`super::frustum::sphere_margin`]).
    pub margin: f32,
}

/// Per cell: the lights that pass, and the lights too close to call.
#[derive(Debug, Clone, PartialEq)]
pub struct CellLists {
    pub dims: [u32; 3],
    /// Sorted light indices per cell.
    pub lists: Vec<Vec<u32>>,
    /// Per cell, the lights (listed or not) whose result is within tolerance.
    pub borderline: Vec<Vec<Borderline>>,
}

impl CellLists {
    /// Total number of list entries.
    pub fn total_entries(&self) -> usize {
        self.lists.iter().map(Vec::len).sum()
    }
}

/// Tolerance of a sphere test in `f32`, relative to the magnitudes involved.
///
/// The GPU builds the same planes and depth bounds in `f32` with a different operation order, so
/// its margins differ from ours by a few ULPs of `|c| + r` (plane normalisation, matrix rows,
/// depth unprojection). `1e-4` relative is about a thousand ULPs: far above that noise, far below
/// any geometric feature of a test scene.
pub fn tolerance(center: Vec3, radius: f32) -> f32 {
    1e-4 * (center.length() + radius).max(1.0)
}

/// Culls view-space `lights` for every cell of `method`.
pub fn cull(
    camera: &CullCamera,
    depth: &DepthBuffer,
    lights_view: &[LightSphere],
    method: Method,
) -> CellLists {
    let dims = method.dims(camera.width, camera.height);
    let cells = (dims[0] * dims[1] * dims[2]) as usize;
    let mut out = CellLists {
        dims,
        lists: vec![Vec::new(); cells],
        borderline: vec![Vec::new(); cells],
    };
    match method {
        Method::Tiled { tile } | Method::Depth25 { tile } => {
            let with_mask = matches!(method, Method::Depth25 { .. });
            for j in 0..dims[1] {
                for i in 0..dims[0] {
                    let Some(bounds) = TileDepth::gather(camera, depth, tile, i, j) else {
                        continue; // sky only: no surface, no lights
                    };
                    let planes = tile_planes(camera, tile, i, j, bounds.min, bounds.max);
                    let mask = with_mask.then_some(&bounds);
                    let cell = (j * dims[0] + i) as usize;
                    test_lights(&planes, mask, lights_view, cell, &mut out);
                }
            }
        }
        Method::Clustered { grid, skip_empty } => {
            let occupied = skip_empty.then(|| cluster_occupancy(camera, depth, method, cells));
            for k in 0..grid.z {
                for j in 0..grid.y {
                    for i in 0..grid.x {
                        let cell = ((k * grid.y + j) * grid.x + i) as usize;
                        if occupied.as_ref().is_some_and(|o| !o[cell]) {
                            continue;
                        }
                        let planes = cluster_planes(camera, grid, i, j, k);
                        test_lights(&planes, None, lights_view, cell, &mut out);
                    }
                }
            }
        }
    }
    out
}

fn test_lights(
    planes: &[Plane],
    mask: Option<&TileDepth>,
    lights: &[LightSphere],
    cell: usize,
    out: &mut CellLists,
) {
    for (index, light) in lights.iter().enumerate() {
        let eps = tolerance(light.center, light.radius);
        let margin = sphere_margin(planes, light.center, light.radius);
        let mut passes = margin >= 0.0;
        let mut borderline = margin.abs() <= eps;
        if let Some(tile) = mask.filter(|_| margin > -eps) {
            let d = -light.center.z;
            passes &= tile.overlaps(d - light.radius, d + light.radius);
            // Would a slightly smaller or larger sphere flip the mask test?
            let shrunk = tile.overlaps(d - light.radius + eps, d + light.radius - eps);
            let grown = tile.overlaps(d - light.radius - eps, d + light.radius + eps);
            borderline |= shrunk != grown;
        }
        if passes {
            out.lists[cell].push(index as u32);
        }
        if borderline {
            out.borderline[cell].push(Borderline {
                light: index as u32,
                margin,
            });
        }
    }
}

fn tile_planes(camera: &CullCamera, tile: u32, i: u32, j: u32, near: f32, far: f32) -> [Plane; 6] {
    let (x0, y1) = camera.pixel_to_ndc((i * tile) as f32, (j * tile) as f32);
    let (x1, y0) = camera.pixel_to_ndc(((i + 1) * tile) as f32, ((j + 1) * tile) as f32);
    let [l, r, b, t] = tile_side_planes(camera.projection, x0, x1, y0, y1);
    [l, r, b, t, Plane::near(near), Plane::far(far)]
}

fn cluster_planes(camera: &CullCamera, grid: ClusterGrid, i: u32, j: u32, k: u32) -> [Plane; 6] {
    let (w, h) = (camera.width, camera.height);
    let (x0, y1) = camera.pixel_to_ndc(
        ClusterGrid::column_start(i, grid.x, w) as f32,
        ClusterGrid::column_start(j, grid.y, h) as f32,
    );
    let (x1, y0) = camera.pixel_to_ndc(
        ClusterGrid::column_start(i + 1, grid.x, w) as f32,
        ClusterGrid::column_start(j + 1, grid.y, h) as f32,
    );
    let [l, r, b, t] = tile_side_planes(camera.projection, x0, x1, y0, y1);
    let far = grid.slice_start(k + 1).min(f32::MAX);
    [
        l,
        r,
        b,
        t,
        Plane::near(grid.slice_start(k)),
        Plane::far(far),
    ]
}

fn cluster_occupancy(
    camera: &CullCamera,
    depth: &DepthBuffer,
    method: Method,
    cells: usize,
) -> Vec<bool> {
    let mut occupied = vec![false; cells];
    for_each_surface_sample(camera, depth, |x, y, p| {
        occupied[method.cell_of(camera.width, camera.height, x, y, -p.z)] = true;
    });
    occupied
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

/// A tile's view-depth range over its surface samples, and its 2.5D geometry mask.
#[derive(Debug, Clone, Copy, PartialEq)]
struct TileDepth {
    min: f32,
    max: f32,
    geometry_mask: u32,
}

impl TileDepth {
    fn gather(camera: &CullCamera, depth: &DepthBuffer, tile: u32, i: u32, j: u32) -> Option<Self> {
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
        };
        for d in depths {
            tile.geometry_mask |= 1 << tile.cell(d);
        }
        Some(tile)
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
    fn overlaps(&self, lo: f32, hi: f32) -> bool {
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
