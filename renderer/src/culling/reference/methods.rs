//! The three culling methods on the CPU: tiled, 2.5D (tiled with a 32-cell depth mask) and
//! clustered (screen tiles × exponential depth slices), each behind the same two-level
//! hierarchy as the GPU: a light is listed in a cell only if it also passes its 128×128-pixel
//! super-tile's frustum (which never removes a light that touches the cell, see [`cull`]).
//! Decals are oriented boxes ([`cull_boxes`]): tested as their bounding sphere and as a box.

use glam::Vec3;

use super::Plane;
use super::cell_bounds::{
    FroxelBox, TileDepth, box_margin, camera_range, froxel_box, has_sky, side_planes, with_depth,
};
use super::cells::{Borderline, CellLists};
use super::frustum::sphere_margin;
use super::{CullCamera, DepthBuffer, LightSphere};
use super::{Method, SUPER_TILE_PIXELS};
use crate::decals::OrientedBox;

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
