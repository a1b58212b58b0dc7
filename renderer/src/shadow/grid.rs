//! A uniform grid over the shadow casters' bounds, so that culling a region afresh (a new or
//! moved light view, an uncached frame) tests the casters near the region's frustum instead of
//! every caster of the scene. A caster sits in every cell its box overlaps; one spanning many
//! cells (a ground plane) sits in a list every query returns.
//!
//! Whether a caster reaches a region is [`RegionTest::reaches`]: its box meets every plane's
//! inner side and the box of the region's clip volume (the planes alone keep boxes beside a
//! frustum's corners). Every caster that passes lies in the cells the volume's box overlaps,
//! so culling through the grid keeps exactly what testing every caster keeps.

use glam::{Mat4, UVec3, Vec3, Vec4};

use super::views::Frustum;
use crate::scene::Aabb;

/// The test of boxes against one region's clip volume.
#[derive(Debug, Clone, Copy)]
pub struct RegionTest {
    frustum: Frustum,
    /// The volume's world box; `None` for a volume reaching infinity.
    bounds: Option<Aabb>,
}

impl RegionTest {
    pub fn new(clip_from_world: Mat4) -> Self {
        Self {
            frustum: Frustum::from_clip(clip_from_world),
            bounds: clip_box(clip_from_world),
        }
    }

    /// Whether `b` may reach the volume (never false for a box inside it; empty boxes reach
    /// nothing).
    pub fn reaches(&self, b: &Aabb) -> bool {
        self.frustum.intersects_aabb(b)
            && self
                .bounds
                .is_none_or(|v| b.min.cmple(v.max).all() && b.max.cmpge(v.min).all())
    }
}

/// The grid of one caster list.
#[derive(Debug, Clone)]
pub struct CasterGrid {
    origin: Vec3,
    cell: Vec3,
    dims: UVec3,
    /// Caster indices per cell, x fastest.
    cells: Vec<Vec<u32>>,
    /// Casters spanning more than [`CasterGrid::LARGE`] cells: candidates of every query.
    large: Vec<u32>,
}

impl CasterGrid {
    /// Cells per axis at most.
    const MAX_DIM: u32 = 48;
    /// A caster over more cells than this is kept apart.
    const LARGE: u32 = 64;

    /// The grid of the casters whose boxes are `boxes`, in caster order (empty boxes, which
    /// reach nothing, left out): about one cell per two casters, cubic cells as far as the
    /// bounds allow.
    pub fn new(boxes: &[Aabb]) -> Self {
        let bounds = boxes.iter().fold(Aabb::EMPTY, |b, &c| b.union(c));
        let extent = if bounds.is_empty() {
            Vec3::ONE
        } else {
            (bounds.max - bounds.min).max(Vec3::splat(1e-3))
        };
        let target = (boxes.len() as f32 / 2.0).max(1.0);
        let side = (extent.x * extent.y * extent.z / target).cbrt();
        let dims = (extent / side)
            .ceil()
            .clamp(Vec3::ONE, Vec3::splat(Self::MAX_DIM as f32))
            .as_uvec3();
        let mut grid = Self {
            origin: if bounds.is_empty() {
                Vec3::ZERO
            } else {
                bounds.min
            },
            cell: extent / dims.as_vec3(),
            dims,
            cells: vec![Vec::new(); (dims.x * dims.y * dims.z) as usize],
            large: Vec::new(),
        };
        for (i, b) in boxes.iter().enumerate() {
            if b.is_empty() {
                continue;
            }
            let (lo, hi) = grid.range(*b);
            let span = (hi - lo + UVec3::ONE).element_product();
            if span > Self::LARGE {
                grid.large.push(i as u32);
                continue;
            }
            for z in lo.z..=hi.z {
                for y in lo.y..=hi.y {
                    for x in lo.x..=hi.x {
                        let at = grid.index(UVec3::new(x, y, z));
                        grid.cells[at].push(i as u32);
                    }
                }
            }
        }
        grid
    }

    /// The casters whose cells meet the box of `test`'s volume (indices, ascending, without
    /// repeats): every caster `test` can keep is among them. `None` when the volume has no
    /// finite box or covers most of the grid: then every caster is a candidate.
    pub fn candidates(&self, test: &RegionTest) -> Option<Vec<u32>> {
        let query = test.bounds?;
        let (lo, hi) = self.range(query);
        let cells = (hi - lo + UVec3::ONE).element_product();
        if cells * 2 > self.cells.len() as u32 {
            return None;
        }
        let mut out = self.large.clone();
        for z in lo.z..=hi.z {
            for y in lo.y..=hi.y {
                for x in lo.x..=hi.x {
                    out.extend_from_slice(&self.cells[self.index(UVec3::new(x, y, z))]);
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        Some(out)
    }

    /// The cells `b` overlaps, clamped to the grid (a box outside it gets the nearest border
    /// cells: a superset, which the exact test trims).
    fn range(&self, b: Aabb) -> (UVec3, UVec3) {
        let cell = |p: Vec3| {
            ((p - self.origin) / self.cell)
                .floor()
                .clamp(Vec3::ZERO, (self.dims - UVec3::ONE).as_vec3())
                .as_uvec3()
        };
        (cell(b.min), cell(b.max))
    }

    fn index(&self, c: UVec3) -> usize {
        (c.x + self.dims.x * (c.y + self.dims.y * c.z)) as usize
    }
}

/// The world box of the clip volume of `clip_from_world` (x, y in [-1, 1], z in [0, 1]), or
/// `None` where a corner is not finite.
fn clip_box(clip_from_world: Mat4) -> Option<Aabb> {
    let world_from_clip = clip_from_world.inverse();
    let mut b = Aabb::EMPTY;
    for i in 0..8 {
        let corner = Vec4::new(
            if i & 1 == 0 { -1.0 } else { 1.0 },
            if i & 2 == 0 { -1.0 } else { 1.0 },
            if i & 4 == 0 { 0.0 } else { 1.0 },
            1.0,
        );
        let p = world_from_clip * corner;
        if p.w.abs() < 1e-12 {
            return None;
        }
        let p = p.truncate() / p.w;
        if !p.is_finite() {
            return None;
        }
        b = b.with_point(p);
    }
    Some(b)
}

#[cfg(test)]
mod tests {
    use glam::{Mat4, Vec3, camera::rh};

    use super::{CasterGrid, RegionTest};
    use crate::scene::Aabb;
    use crate::shadow::views::cube_views;

    /// A 64-bit LCG, floats in `[lo, hi)`.
    struct Lcg(u64);

    impl Lcg {
        fn range(&mut self, lo: f32, hi: f32) -> f32 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            lo + (hi - lo) * ((self.0 >> 40) as f32 / (1u64 << 24) as f32)
        }

        fn point(&mut self, lo: f32, hi: f32) -> Vec3 {
            Vec3::new(
                self.range(lo, hi),
                self.range(0.0, 30.0),
                self.range(lo, hi),
            )
        }
    }

    #[test]
    fn culling_through_the_grid_finds_what_testing_every_caster_finds() {
        let mut rng = Lcg(11);
        let mut casters: Vec<Aabb> = (0..3_000u32)
            .map(|_| {
                let at = rng.point(-400.0, 400.0);
                let half = Vec3::new(
                    rng.range(0.2, 8.0),
                    rng.range(0.2, 20.0),
                    rng.range(0.2, 8.0),
                );
                Aabb {
                    min: at - half,
                    max: at + half,
                }
            })
            .collect();
        // A ground under everything (kept apart: it spans every cell) and removed draws.
        casters[0] = Aabb {
            min: Vec3::new(-420.0, -1.0, -420.0),
            max: Vec3::new(420.0, 0.0, 420.0),
        };
        for c in casters.iter_mut().skip(1).step_by(97) {
            *c = Aabb::EMPTY;
        }
        let grid = CasterGrid::new(&casters);
        assert_eq!(grid.large, [0], "only the ground spans too many cells");
        let mut views: Vec<Mat4> = Vec::new();
        for _ in 0..12 {
            let centre = rng.point(-380.0, 380.0);
            let range = rng.range(5.0, 60.0);
            views.extend(
                cube_views(centre, range, 256, 2)
                    .iter()
                    .map(|v| v.clip_from_world),
            );
        }
        // A cascade-like box and a view reaching infinity (no finite box: every caster).
        let look = rh::view::look_at_mat4(Vec3::new(0.0, 200.0, 0.0), Vec3::ZERO, Vec3::Z);
        views.push(rh::proj::directx::orthographic(-60.0, 60.0, -60.0, 60.0, 1.0, 400.0) * look);
        let infinite = rh::proj::directx::perspective_infinite_reverse(1.0, 1.0, 0.5) * look;
        assert!(grid.candidates(&RegionTest::new(infinite)).is_none());
        views.push(infinite);
        let mut found_any = 0;
        for (v, &clip) in views.iter().enumerate() {
            let test = RegionTest::new(clip);
            let reaches = |&i: &u32| test.reaches(&casters[i as usize]);
            let every: Vec<u32> = (0..casters.len() as u32).filter(reaches).collect();
            let through_grid: Vec<u32> = match grid.candidates(&test) {
                Some(near) => {
                    assert!(near.len() < casters.len() / 4, "view {v}: the grid narrows");
                    near.into_iter().filter(reaches).collect()
                }
                None => every.clone(),
            };
            assert_eq!(through_grid, every, "view {v}");
            found_any += usize::from(every.len() > 1);
        }
        assert!(
            found_any > 20,
            "most views reach casters besides the ground"
        );
    }
}
