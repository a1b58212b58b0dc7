//! The reference under an orthographic camera: a tile's frustum has parallel sides, its
//! view-space box the tile's own rectangle at every depth, and every light that reaches a
//! sample is in the sample's list for every method (the box test included, no MSAA).
//!
//! Sample positions and tile rectangles are worked out here from the orthographic camera's
//! definition (half extents, linear depth), not through the reference's unprojection.

use glam::{Mat4, Vec3};

use super::cell_bounds::froxel_box;
use super::{CullCamera, DepthBuffer, LightSphere, Method, cull};
use crate::culling::reference::{ClusterGrid, cells::CellLists};

const HALF_W: f32 = 4.0;
const HALF_H: f32 = 3.0;
const NEAR: f32 = 0.5;
const FAR: f32 = 50.0;
const W: u32 = 64;
const H: u32 = 48;

fn camera() -> CullCamera {
    CullCamera {
        view: Mat4::IDENTITY,
        projection: glam::camera::rh::proj::directx::orthographic(
            -HALF_W, HALF_W, -HALF_H, HALF_H, NEAR, FAR,
        ),
        width: W,
        height: H,
    }
}

/// View-space `xy` of pixel position `(px, py)` (pixel corners at integers).
fn pixel_xy(px: f32, py: f32) -> (f32, f32) {
    (
        -HALF_W + 2.0 * HALF_W * px / W as f32,
        HALF_H - 2.0 * HALF_H * py / H as f32,
    )
}

/// View depth of the surface at pixel `(x, y)`: a slope on the left, a step, sky at the
/// bottom-right corner.
fn surface_depth(x: u32, y: u32) -> Option<f32> {
    if x > 48 && y > 36 {
        return None;
    }
    Some(if x < 30 {
        4.0 + 0.25 * x as f32 + 0.1 * y as f32
    } else {
        12.0 + 0.05 * y as f32
    })
}

fn depth_buffer() -> DepthBuffer {
    let mut depth = Vec::new();
    for y in 0..H {
        for x in 0..W {
            // Orthographic wgpu depth is linear in view depth: 0 at the near plane, 1 at far.
            depth.push(surface_depth(x, y).map_or(1.0, |d| (d - NEAR) / (FAR - NEAR)));
        }
    }
    DepthBuffer {
        width: W,
        height: H,
        samples: 1,
        depth,
    }
}

/// Seeded lights across the view volume, radii 0.3 to 2.
fn lights() -> Vec<LightSphere> {
    let mut rng = crate::demo::Rng::new(36);
    (0..160)
        .map(|_| LightSphere {
            center: Vec3::new(
                rng.range(-HALF_W - 1.0, HALF_W + 1.0),
                rng.range(-HALF_H - 1.0, HALF_H + 1.0),
                -rng.range(2.0, 16.0),
            ),
            radius: rng.range(0.3, 2.0),
        })
        .collect()
}

#[test]
fn a_tiles_box_is_its_rectangle_at_every_depth() {
    let (tile, i, j) = (8, 3, 2);
    let b = froxel_box(&camera(), tile, i, j, 5.0, 20.0);
    let (x0, y1) = pixel_xy((i * tile) as f32, (j * tile) as f32);
    let (x1, y0) = pixel_xy(((i + 1) * tile) as f32, ((j + 1) * tile) as f32);
    let inside = [
        Vec3::new(x0, y0, -5.0),
        Vec3::new(x1, y1, -20.0),
        Vec3::new(x0, y1, -12.0),
    ];
    for p in inside {
        assert!(b.distance(p) < 1e-4, "{p} lies in the tile's frustum");
    }
    // Just outside each side, at both depths: the sides do not spread with depth.
    for z in [-5.0, -20.0] {
        for p in [
            Vec3::new(x0 - 0.01, y0, z),
            Vec3::new(x1 + 0.01, y0, z),
            Vec3::new(x0, y0 - 0.01, z),
            Vec3::new(x0, y1 + 0.01, z),
        ] {
            let d = b.distance(p);
            assert!((d - 0.01).abs() < 1e-3, "{p} is 0.01 outside, not {d}");
        }
    }
}

/// Every light whose sphere contains a sample's surface point is in the sample's list.
fn assert_conservative(method: Method, lists: &CellLists) -> usize {
    let lights = lights();
    let mut checked = 0;
    for y in 0..H {
        for x in 0..W {
            let Some(d) = surface_depth(x, y) else {
                continue;
            };
            let (px, py) = pixel_xy(x as f32 + 0.5, y as f32 + 0.5);
            let p = Vec3::new(px, py, -d);
            let cell = method.cell_of(W, H, x, y, d);
            for (k, l) in lights.iter().enumerate() {
                if l.center.distance(p) > l.radius {
                    continue;
                }
                checked += 1;
                let k = k as u32;
                let listed = lists.lists[cell].binary_search(&k).is_ok();
                let close = lists.borderline[cell].iter().any(|b| b.light == k);
                assert!(
                    listed || close,
                    "{method:?}: light {k} reaches pixel ({x}, {y}) at {p} but cell {cell} \
                     lacks it"
                );
            }
        }
    }
    checked
}

#[test]
fn every_method_lists_every_light_that_reaches_a_sample() {
    let grid = ClusterGrid {
        tile: 8,
        slices: 16,
        near: NEAR,
        far: FAR,
    };
    let methods = [
        Method::tiled(8),
        Method::depth25(8),
        Method::tiled(16),
        Method::Clustered {
            grid,
            skip_empty: false,
        },
        Method::Clustered {
            grid,
            skip_empty: true,
        },
    ];
    let (camera, depth, lights) = (camera(), depth_buffer(), lights());
    for method in methods {
        let lists = cull(&camera, &depth, &lights, method);
        let checked = assert_conservative(method, &lists);
        assert!(checked > 2000, "{method:?}: only {checked} pairs checked");
        // Not everything everywhere: the tiles' frustums do narrow the lists.
        let tiles = (W / method.tile()) * (H / method.tile());
        assert!(
            lists.total_entries() < lights.len() * tiles as usize,
            "{method:?}: {} entries",
            lists.total_entries()
        );
    }
}
