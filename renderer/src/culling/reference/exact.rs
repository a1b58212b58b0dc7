//! The exact answer: per surface sample, the lights whose sphere contains the sample's point,
//! and the cull efficiency of a method's lists against it.
//!
//! This does not use the culling code at all: candidates come from a uniform grid over the
//! points' bounding box, each light entered in every grid cell its bounding box touches.

use glam::{UVec3, Vec3};

use super::Method;
use super::cell_bounds::for_each_surface_sample;
use super::cells::CellLists;

/// Calls `f(x, y, view_position)` for every sample of `depth` that holds a surface.
pub fn for_each_surface_sample_pub(
    camera: &CullCamera,
    depth: &DepthBuffer,
    f: impl FnMut(u32, u32, Vec3),
) {
    for_each_surface_sample(camera, depth, f);
}
use super::{CullCamera, DepthBuffer, LightSphere};
pub use crate::culling::depth::Efficiency;

/// Lights whose sphere contains view-space point `p`, sorted.
pub fn lights_reaching(grid: &LightGrid, lights_view: &[LightSphere], p: Vec3) -> Vec<u32> {
    grid.candidates(p)
        .iter()
        .copied()
        .filter(|&i| {
            let l = lights_view[i as usize];
            l.center.distance_squared(p) <= l.radius * l.radius
        })
        .collect()
}

/// Measures how many listed lights each sample pays for against how many reach it.
pub fn cull_efficiency(
    camera: &CullCamera,
    depth: &DepthBuffer,
    lights_view: &[LightSphere],
    method: Method,
    lists: &CellLists,
) -> Efficiency {
    let grid = LightGrid::new(camera, depth, lights_view);
    let mut e = Efficiency {
        listed: 0,
        reaching: 0,
    };
    for_each_surface_sample(camera, depth, |x, y, p| {
        let cell = method.cell_of(camera.width, camera.height, x, y, -p.z);
        e.listed += lists.lists[cell].len() as u64;
        e.reaching += lights_reaching(&grid, lights_view, p).len() as u64;
    });
    e
}

/// A uniform grid of light candidates over the bounding box of a depth buffer's surface points.
#[derive(Debug, Clone)]
pub struct LightGrid {
    min: Vec3,
    cell_size: Vec3,
    res: UVec3,
    cells: Vec<Vec<u32>>,
}

impl LightGrid {
    const RES: u32 = 32;

    pub fn new(camera: &CullCamera, depth: &DepthBuffer, lights_view: &[LightSphere]) -> Self {
        let (mut min, mut max) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for_each_surface_sample(camera, depth, |_, _, p| {
            min = min.min(p);
            max = max.max(p);
        });
        if min.x > max.x {
            (min, max) = (Vec3::ZERO, Vec3::ZERO);
        }
        let res = UVec3::splat(Self::RES);
        let cell_size = ((max - min) / res.as_vec3()).max(Vec3::splat(1e-6));
        let mut grid = Self {
            min,
            cell_size,
            res,
            cells: vec![Vec::new(); (Self::RES * Self::RES * Self::RES) as usize],
        };
        for (i, l) in lights_view.iter().enumerate() {
            let lo = grid.coord(l.center - l.radius);
            let hi = grid.coord(l.center + l.radius);
            for z in lo.z..=hi.z {
                for y in lo.y..=hi.y {
                    for x in lo.x..=hi.x {
                        let c = grid.index(UVec3::new(x, y, z));
                        grid.cells[c].push(i as u32);
                    }
                }
            }
        }
        grid
    }

    fn coord(&self, p: Vec3) -> UVec3 {
        let c = ((p - self.min) / self.cell_size).floor();
        c.clamp(Vec3::ZERO, (self.res - 1).as_vec3()).as_uvec3()
    }

    fn index(&self, c: UVec3) -> usize {
        ((c.z * self.res.y + c.y) * self.res.x + c.x) as usize
    }

    /// Lights whose bounding box touches the grid cell of `p` (a superset of those reaching it).
    pub fn candidates(&self, p: Vec3) -> &[u32] {
        &self.cells[self.index(self.coord(p))]
    }
}
