//! The three culling methods on the CPU: tiled, 2.5D (tiled with a 32-cell depth mask) and
//! clustered (screen tiles × exponential depth slices), each behind the same two-level
//! hierarchy as the GPU: a light is listed in a cell only if it also passes its 128×128-pixel
//! super-tile's frustum (which never removes a light that touches the cell, see [`cull`]).
//! Decals are oriented boxes ([`cull_boxes`]): tested as their bounding sphere and as a box.

use glam::Vec3;

use super::frustum::{Plane, sphere_margin, tile_side_planes};
use super::{CullCamera, DepthBuffer, LightSphere};
use crate::decals::OrientedBox;

/// Number of depth cells in a 2.5D tile mask.
pub const DEPTH_MASK_CELLS: u32 = 32;
/// Edge of a super-tile in pixels.
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

/// What a cell lists: a light's sphere, or a decal's box (both in view space).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Shape {
    Sphere(LightSphere),
    Box(OrientedBox),
}

impl Shape {
    /// The sphere every level tests (a box's bounding sphere: the super-tile level and the
    /// first test of the fine level).
    fn sphere(&self) -> LightSphere {
        match *self {
            Self::Sphere(s) => s,
            Self::Box(b) => {
                let (center, radius) = b.bounding_sphere();
                LightSphere { center, radius }
            }
        }
    }
}

/// Culls view-space `lights` for every cell of `method`, through the hierarchy the GPU uses: a
/// light is listed in a cell when it passes the cell's test and its super-tile's.
///
/// The super-tile test cannot remove a light that touches the cell: the super-tile's frustum
/// contains each of its tiles' frusta (its depth range spans theirs), so a sphere outside one of
/// its planes is outside the cell too. It only removes plane-test false positives.
pub fn cull(
    camera: &CullCamera,
    depth: &DepthBuffer,
    lights_view: &[LightSphere],
    method: Method,
) -> CellLists {
    cull_levels(camera, depth, &spheres(lights_view), method, true)
}

/// Culls view-space decal boxes for every cell of `method`, with the lights' hierarchy: a box
/// is listed in a cell when its bounding sphere would be (as a light) and the box itself
/// reaches the cell: no cell plane has all its corners behind it, its axis-aligned bounds meet
/// the cell's view-space box where lights are tested against that box (no MSAA), and its depth
/// span meets the 2.5D mask. Lists hold box indices in ascending order.
pub fn cull_boxes(
    camera: &CullCamera,
    depth: &DepthBuffer,
    boxes_view: &[OrientedBox],
    method: Method,
    hierarchical: bool,
) -> CellLists {
    let shapes: Vec<Shape> = boxes_view.iter().copied().map(Shape::Box).collect();
    cull_levels(camera, depth, &shapes, method, hierarchical)
}

fn spheres(lights: &[LightSphere]) -> Vec<Shape> {
    lights.iter().copied().map(Shape::Sphere).collect()
}

/// [`cull`] without the super-tile level: every cell tests every light (the GPU's brute-force
/// variant).
pub fn cull_brute_force(
    camera: &CullCamera,
    depth: &DepthBuffer,
    lights_view: &[LightSphere],
    method: Method,
) -> CellLists {
    cull_levels(camera, depth, &spheres(lights_view), method, false)
}

fn cull_levels(
    camera: &CullCamera,
    depth: &DepthBuffer,
    items: &[Shape],
    method: Method,
    hierarchical: bool,
) -> CellLists {
    let dims = method.dims(camera.width, camera.height);
    let tile_count = dims[0] * dims[1];
    let cells = (tile_count * dims[2]) as usize;
    let mut out = CellLists {
        dims,
        lists: vec![Vec::new(); cells],
        borderline: vec![Vec::new(); cells],
    };
    let tile = method.tile();
    let per_super = SUPER_TILE_PIXELS / tile;
    let super_x = camera.width.div_ceil(SUPER_TILE_PIXELS);
    let super_planes = every_super_tile_planes(camera, depth, method, hierarchical);
    let (camera_near, camera_far) = camera_range(camera);
    // The view-space box of each cell narrows its list only where every shaded point is a
    // sample position: without MSAA (see `box_test` in the kernels' parameters).
    let boxes = depth.samples == 1;
    for j in 0..dims[1] {
        for i in 0..dims[0] {
            let tile_index = j * dims[0] + i;
            let bounds = TileDepth::gather(camera, depth, tile, i, j);
            let sides = side_planes(camera, tile, i, j);
            // A super-tile without surfaces (and nothing else to list) has no candidates.
            let super_planes = super_planes[((j / per_super) * super_x + i / per_super) as usize];
            let candidates = Candidates {
                coarse: super_planes.as_ref().map(|p| p.as_slice()),
                none: hierarchical && super_planes.is_none(),
            };
            match method {
                Method::Tiled { transparent, .. } | Method::Depth25 { transparent, .. } => {
                    let mask = matches!(method, Method::Depth25 { .. });
                    if let Some(b) = &bounds {
                        let planes = with_depth(sides, b.min, b.max);
                        let frustum_box = froxel_box(camera, tile, i, j, b.min, b.max);
                        let test = FineTest {
                            planes: &planes,
                            mask: mask.then_some(b),
                            froxel: boxes.then_some(&frustum_box),
                        };
                        let cell = tile_index as usize;
                        test_lights(&test, &candidates, items, cell, &mut out);
                    }
                    if transparent {
                        // Blended surfaces above a sky sample can be as far as the far plane.
                        let far = match &bounds {
                            Some(b) if !has_sky(depth, tile, i, j) => b.max,
                            _ => camera_far,
                        };
                        let planes = with_depth(sides, camera_near, far);
                        let frustum_box = froxel_box(camera, tile, i, j, camera_near, far);
                        let test = FineTest {
                            planes: &planes,
                            mask: None,
                            froxel: boxes.then_some(&frustum_box),
                        };
                        let cell = (tile_count + tile_index) as usize;
                        test_lights(&test, &candidates, items, cell, &mut out);
                    }
                }
                Method::Clustered { grid, skip_empty } => {
                    let occupied = bounds.as_ref().map_or(0, |b| b.slices(grid));
                    for k in 0..grid.slices {
                        if skip_empty && occupied & (1 << k) == 0 {
                            continue;
                        }
                        let (mut zn, mut zf) = (grid.slice_start(k), grid.slice_start(k + 1));
                        if let (true, Some(b)) = (skip_empty, &bounds) {
                            // Only samples are shaded here: clip the froxel to their range.
                            (zn, zf) = (zn.max(b.min), zf.min(b.max));
                        }
                        let planes = with_depth(sides, zn, zf.min(f32::MAX));
                        let froxel = (zf.is_finite() && boxes)
                            .then(|| froxel_box(camera, tile, i, j, zn, zf));
                        let test = FineTest {
                            planes: &planes,
                            mask: None,
                            froxel: froxel.as_ref(),
                        };
                        let cell = (k * tile_count + tile_index) as usize;
                        test_lights(&test, &candidates, items, cell, &mut out);
                    }
                }
            }
        }
    }
    out
}

/// Whether any sample of the square cell `(i, j)` of `size` pixels (inside the screen) is sky.
fn has_sky(depth: &DepthBuffer, size: u32, i: u32, j: u32) -> bool {
    let xs = (i * size)..((i + 1) * size).min(depth.width);
    xs.flat_map(|x| {
        ((j * size)..((j + 1) * size).min(depth.height))
            .flat_map(move |y| (0..depth.samples).map(move |s| (x, y, s)))
    })
    .any(|(x, y, s)| !DepthBuffer::is_surface(depth.get(x, y, s)))
}

/// View depths of the near and far planes (wgpu depth 0 and 1).
fn camera_range(camera: &CullCamera) -> (f32, f32) {
    (
        -camera.unproject(0.0, 0.0, 0.0).z,
        -camera.unproject(0.0, 0.0, 1.0).z,
    )
}

/// [`super_tile_planes`] of every super-tile, row by row (all `None` without the hierarchy).
fn every_super_tile_planes(
    camera: &CullCamera,
    depth: &DepthBuffer,
    method: Method,
    hierarchical: bool,
) -> Vec<Option<[Plane; 6]>> {
    let super_x = camera.width.div_ceil(SUPER_TILE_PIXELS);
    let super_y = camera.height.div_ceil(SUPER_TILE_PIXELS);
    (0..super_y)
        .flat_map(|sj| (0..super_x).map(move |si| (si, sj)))
        .map(|(si, sj)| {
            if hierarchical {
                super_tile_planes(camera, depth, method, si, sj)
            } else {
                None
            }
        })
        .collect()
}

/// The planes of super-tile `(si, sj)` for `method`, or `None` when it lists nothing.
fn super_tile_planes(
    camera: &CullCamera,
    depth: &DepthBuffer,
    method: Method,
    si: u32,
    sj: u32,
) -> Option<[Plane; 6]> {
    let sides = side_planes(camera, SUPER_TILE_PIXELS, si, sj);
    let (near, far) = match method {
        // Every slice listed: no depth bound at all.
        Method::Clustered {
            skip_empty: false, ..
        } => (0.0, f32::MAX),
        m if m.transparent_lists() => {
            // From the near plane to the farthest depth its tiles' blended surfaces reach.
            let (near, far) = camera_range(camera);
            match TileDepth::gather(camera, depth, SUPER_TILE_PIXELS, si, sj) {
                Some(b) if !has_sky(depth, SUPER_TILE_PIXELS, si, sj) => (near, b.max),
                _ => (near, far),
            }
        }
        _ => {
            let b = TileDepth::gather(camera, depth, SUPER_TILE_PIXELS, si, sj)?;
            (b.min, b.max)
        }
    };
    Some(with_depth(sides, near, far))
}

/// Which lights a cell may list: its super-tile's survivors (or all, without the hierarchy).
struct Candidates<'a> {
    coarse: Option<&'a [Plane]>,
    /// The super-tile lists nothing.
    none: bool,
}

/// A cell's own test: planes, and optionally the 2.5D mask or the froxel's bounding box.
struct FineTest<'a> {
    planes: &'a [Plane],
    mask: Option<&'a TileDepth>,
    froxel: Option<&'a FroxelBox>,
}

fn test_lights(
    test: &FineTest<'_>,
    candidates: &Candidates<'_>,
    shapes: &[Shape],
    cell: usize,
    out: &mut CellLists,
) {
    if candidates.none {
        return;
    }
    for (index, shape) in shapes.iter().enumerate() {
        let light = shape.sphere();
        let eps = tolerance(light.center, light.radius);
        // Every test's margin (≥ 0 passes); the item passes when all do, and is a close call
        // when any of them is within the tolerance.
        let mut margins = vec![sphere_margin(test.planes, light.center, light.radius)];
        if let Some(coarse) = candidates.coarse {
            margins.push(sphere_margin(coarse, light.center, light.radius));
        }
        if let Some(froxel) = test.froxel {
            margins.push(light.radius - froxel.distance(light.center));
        }
        // A box's depth span for the mask: the sphere's, or the box's own.
        let mut half_depth = light.radius;
        if let Shape::Box(b) = shape {
            margins.push(box_margin(test.planes, b));
            if let Some(froxel) = test.froxel {
                margins.push(froxel.box_margin(b));
            }
            half_depth = b.radius_along(Vec3::Z);
        }
        let margin = margins.iter().copied().fold(f32::INFINITY, f32::min);
        let close_call = margins.iter().any(|m| m.abs() <= eps);
        let mut passes = margin >= 0.0;
        let mut borderline = close_call;
        if let Some(tile) = test.mask.filter(|_| margin > -eps) {
            let d = -light.center.z;
            passes &= tile.overlaps(d - half_depth, d + half_depth);
            // Would a slightly smaller or larger item flip the mask test?
            let shrunk = tile.overlaps(d - half_depth + eps, d + half_depth - eps);
            let grown = tile.overlaps(d - half_depth - eps, d + half_depth + eps);
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

/// The four side planes of the square cell `(i, j)` of `size` pixels (not clamped to the
/// screen).
fn side_planes(camera: &CullCamera, size: u32, i: u32, j: u32) -> [Plane; 4] {
    let (x0, y1) = camera.pixel_to_ndc((i * size) as f32, (j * size) as f32);
    let (x1, y0) = camera.pixel_to_ndc(((i + 1) * size) as f32, ((j + 1) * size) as f32);
    tile_side_planes(camera.projection, x0, x1, y0, y1)
}

fn with_depth(sides: [Plane; 4], near: f32, far: f32) -> [Plane; 6] {
    let [l, r, b, t] = sides;
    [l, r, b, t, Plane::near(near), Plane::far(far)]
}

/// The view-space bounding box of a froxel: tile `(i, j)` between view depths `zn` and `zf`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct FroxelBox {
    min: Vec3,
    max: Vec3,
}

fn froxel_box(camera: &CullCamera, tile: u32, i: u32, j: u32, zn: f32, zf: f32) -> FroxelBox {
    let mut b = FroxelBox {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };
    for (px, py) in [(i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)] {
        let (nx, ny) = camera.pixel_to_ndc((px * tile) as f32, (py * tile) as f32);
        let p = camera.unproject(nx, ny, 0.5);
        // The corner's ray, scaled to view depth 1, at both depths.
        let ray = p / -p.z;
        for z in [zn, zf] {
            b.min = b.min.min(ray * z);
            b.max = b.max.max(ray * z);
        }
    }
    b
}

impl FroxelBox {
    /// Distance from `p` to the box (0 inside).
    fn distance(&self, p: Vec3) -> f32 {
        p.distance(p.clamp(self.min, self.max))
    }

    /// How far the oriented box's axis-aligned bounds reach into this box along the axis where
    /// they overlap least (negative: the gap where they miss).
    fn box_margin(&self, b: &OrientedBox) -> f32 {
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
fn box_margin(planes: &[Plane], b: &OrientedBox) -> f32 {
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
struct TileDepth {
    min: f32,
    max: f32,
    geometry_mask: u32,
    depths: Vec<f32>,
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
            depths: Vec::new(),
        };
        for &d in &depths {
            tile.geometry_mask |= 1 << tile.cell(d);
        }
        tile.depths = depths;
        Some(tile)
    }

    /// The depth slices of `grid` holding a sample (bit `k` for slice `k`).
    fn slices(&self, grid: ClusterGrid) -> u32 {
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
