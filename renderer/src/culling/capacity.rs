//! The most index-list entries a frame's culling can write, computed on the CPU before the
//! frame, so the index list is sized for the frame it serves: the first frame, and the frame
//! after a jump in light count, radius or camera, are exact like every other.
//!
//! The bound is conservative with respect to the GPU's tests, which only ever remove cells:
//! - an item (a light's bounding sphere, a decal's box through a sphere around it) can enter a
//!   tile's list only if it clears the tile's four side planes. Those planes are planes through
//!   the eye (or parallel, orthographic), so an item clears them exactly when its projection
//!   overlaps the tile; the projection lies inside the screen rectangle of its view-space
//!   bounding cube's eight corners (a projective map keeps the cube's convex hull), widened
//!   here by a pixel. An item whose cube reaches the eye's plane counts every tile; one wholly
//!   behind the eye counts none;
//! - tiled culling keeps at most one entry per list of a tile (an opaque list, and a blended
//!   one when the scene has blended surfaces);
//! - clustered culling lists an item in a tile's depth slice only if the item's depth span
//!   `[d − r, d + r]` overlaps the slice, counted here with one slice of margin either side
//!   for rounding, as the kernel does.
//!
//! Depth masks, tile depth bounds, box tests and super-tile candidates only shrink the lists, so
//! they are ignored. `tests/tests/cull_gpu.rs` checks the bound against what the GPU requests.

use glam::{Mat4, Vec3, Vec4Swizzles as _};

/// How a culling method lays out its lists.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ListLayout {
    /// A list per tile and per list kind (opaque, and blended when present).
    Tiled { lists_per_tile: u32 },
    /// A list per tile and exponential depth slice: slice `k` of `slices` starts at view depth
    /// `near · (far / near)^(k / slices)` (slice 0 at the eye, the last unbounded).
    Clustered { slices: u32, near: f32, far: f32 },
}

/// The screen and camera the lists are built for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridView {
    pub view: Mat4,
    /// A wgpu (depth 0..1) projection, perspective or orthographic.
    pub projection: Mat4,
    pub width: u32,
    pub height: u32,
    pub tile: u32,
}

/// An upper bound on the entries the index list receives for items with world-space bounding
/// spheres `spheres` (`(centre, radius)`), in `layout` over `grid`.
pub fn entry_bound(
    spheres: impl IntoIterator<Item = (Vec3, f32)>,
    grid: &GridView,
    layout: ListLayout,
) -> u64 {
    let tiles_x = grid.width.div_ceil(grid.tile.max(1));
    let tiles_y = grid.height.div_ceil(grid.tile.max(1));
    spheres
        .into_iter()
        .map(|(center, radius)| {
            let tiles = tiles_touched(center, radius, grid, (tiles_x, tiles_y));
            if tiles == 0 {
                return 0;
            }
            let lists = match layout {
                ListLayout::Tiled { lists_per_tile } => u64::from(lists_per_tile),
                ListLayout::Clustered { slices, near, far } => {
                    let depth = -grid.view.transform_point3(center).z;
                    u64::from(slices_touched(depth, radius, slices, near, far))
                }
            };
            tiles * lists
        })
        .sum()
}

/// Tiles whose side planes the sphere can clear (a superset).
fn tiles_touched(
    center: Vec3,
    radius: f32,
    grid: &GridView,
    (tiles_x, tiles_y): (u32, u32),
) -> u64 {
    let all = u64::from(tiles_x) * u64::from(tiles_y);
    let c = grid.view.transform_point3(center);
    if !c.is_finite() || !radius.is_finite() || radius > 1.0e20 {
        return all;
    }
    let r = radius.max(0.0);
    if c.z - r > 0.0 {
        // Wholly behind the eye: no side plane test passes (the kernels require `-c.z + r ≥ 0`).
        return 0;
    }
    let (mut lo, mut hi) = (
        glam::Vec2::splat(f32::INFINITY),
        glam::Vec2::splat(f32::NEG_INFINITY),
    );
    for corner in 0..8u32 {
        let offset = Vec3::new(
            if corner & 1 == 0 { -r } else { r },
            if corner & 2 == 0 { -r } else { r },
            if corner & 4 == 0 { -r } else { r },
        );
        let clip = grid.projection * (c + offset).extend(1.0);
        // A corner at or behind the eye: the projection is unbounded there.
        if clip.w <= 1.0e-6 {
            return all;
        }
        let ndc = clip.xy() / clip.w;
        lo = lo.min(ndc);
        hi = hi.max(ndc);
    }
    let (w, h) = (grid.width as f32, grid.height as f32);
    // NDC to pixels (y down), widened by a pixel against rounding in the kernels' plane tests.
    let x0 = (lo.x * 0.5 + 0.5) * w - 1.0;
    let x1 = (hi.x * 0.5 + 0.5) * w + 1.0;
    let y0 = (0.5 - hi.y * 0.5) * h - 1.0;
    let y1 = (0.5 - lo.y * 0.5) * h + 1.0;
    let span = |a: f32, b: f32, size: f32, count: u32| -> u64 {
        if b < 0.0 || a > size || count == 0 {
            return 0;
        }
        let tile = grid.tile.max(1) as f32;
        let first = (a.max(0.0) / tile).floor() as u64;
        let last = ((b.min(size) / tile).floor() as u64).min(u64::from(count) - 1);
        last.saturating_sub(first) + 1
    };
    span(x0, x1, w, tiles_x) * span(y0, y1, h, tiles_y)
}

/// The slice of view depth `d` (as the kernels' `slice_of`, in f64).
fn slice_of(d: f32, near: f32, far: f32, slices: u32) -> u32 {
    let t = (f64::from(d) / f64::from(near)).ln() / (f64::from(far) / f64::from(near)).ln();
    let k = (t * f64::from(slices)).floor().max(0.0);
    (k as u32).min(slices - 1)
}

/// Depth slices a sphere at view depth `depth` of radius `radius` can be listed in: those its
/// depth span overlaps, one more either side.
fn slices_touched(depth: f32, radius: f32, slices: u32, near: f32, far: f32) -> u32 {
    if slices == 0 {
        return 0;
    }
    if !(depth.is_finite() && radius.is_finite() && near > 0.0 && far > near) || radius > 1.0e20 {
        return slices;
    }
    let (lo, hi) = (depth - radius, depth + radius);
    let first = if lo > near {
        slice_of(lo, near, far, slices).saturating_sub(1)
    } else {
        0
    };
    let last = if hi > near {
        (slice_of(hi, near, far, slices) + 1).min(slices - 1)
    } else {
        1.min(slices - 1)
    };
    last.saturating_sub(first) + 1
}

#[cfg(test)]
#[path = "capacity_tests.rs"]
mod tests;
