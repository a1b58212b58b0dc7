//! Light-grid geometry shared by the culling kernels and the passes that read their lists:
//! view depth, depth slices, tile and froxel cells, frustum planes, and the sphere and
//! oriented-box tests.

/// The cell lookups, frustum tests and 2.5D mask cells of the culling kernels, `forward` and
/// `heatmap`.
/// Every function takes what it needs as parameters (no statics), so each module passes its
/// own parameters uniform's fields.
///
/// Conventions are those of the CPU reference: a froxel is a screen tile in one depth slice;
/// depth slice `k` of `slices` spans view depths
/// `near·(far/near)^(k/slices)` to the next, slice 0 reaching the eye and the last going to
/// infinity.
#[shader_dsl::library]
pub mod light_grid {
    /// The four side planes of a tile or froxel, `n · p + w = 0`, normals pointing inwards.
    pub struct SidePlanes {
        pub left: Vec4,
        pub right: Vec4,
        pub bottom: Vec4,
        pub top: Vec4,
    }

    /// The spread of a screen rectangle's corner rays: view-space `xy` at view depth 1 through
    /// a perspective projection; with `parallel` non-zero (orthographic), the rays are parallel
    /// and `min`, `max` are the rectangle's view-space `xy` at every depth.
    pub struct TileRays {
        pub min: Vec2,
        pub max: Vec2,
        pub parallel: u32,
    }

    /// Cells of the 2.5D depth mask of a tile.
    pub const MASK_CELLS: u32 = 32;

    /// Stands for infinity in plane distances (WGSL has no infinite literal).
    const FAR_AWAY: f32 = 3.0e38;

    /// View depth (distance along −Z) of a depth-buffer value.
    pub fn view_depth(inv_projection: Mat4, d: f32) -> f32 {
        let p = inv_projection * Vec4::new(0.0, 0.0, d, 1.0);
        -p.z / p.w
    }

    /// The depth slice of view depth `d`.
    pub fn slice_of(d: f32, near: f32, far: f32, slices: u32) -> u32 {
        let t = (d / near).ln() / (far / near).ln();
        let k = (t * slices as f32).floor().max(0.0);
        (k as u32).min(slices - 1u32)
    }

    /// View depth where slice `k` starts.
    pub fn slice_start(k: u32, near: f32, far: f32, slices: u32) -> f32 {
        let mut d = 0.0;
        if k >= slices {
            d = FAR_AWAY;
        } else if k > 0u32 {
            d = near * (far / near).powf(k as f32 / slices as f32);
        }
        d
    }

    /// The grid cell of pixel `px` in a tiled grid `tiles_x` tiles across.
    pub fn tile_cell(px: UVec2, tile_size: u32, tiles_x: u32) -> u32 {
        let t = px / tile_size;
        t.y * tiles_x + t.x
    }

    /// The grid cell of pixel `px` in depth slice `slice`: froxels are screen tiles × slices, and
    /// slice `k`'s lists follow the `k` slices before it (`tiles.x · tiles.y` entries each).
    pub fn froxel_cell(px: UVec2, slice: u32, tile_size: u32, tiles: UVec2) -> u32 {
        slice * tiles.x * tiles.y + tile_cell(px, tile_size, tiles.x)
    }

    /// A plane `n · p + w = 0` from a combination of projection rows, normalised.
    pub fn normalized_plane(v: Vec4) -> Vec4 {
        v / v.xyz().length()
    }

    /// Screen tile `tile_xy`'s rectangle in NDC, tiles of `tile` pixels over a `screen`
    /// (pixels, `y` down): `(x0, x1, y0, y1)` with `y` up, so `y0` is the tile's bottom edge.
    pub fn tile_ndc(tile_xy: UVec2, tile: u32, screen: UVec2) -> Vec4 {
        let size = screen.as_vec2();
        let lo = (tile_xy * tile).as_vec2();
        let hi = ((tile_xy + UVec2::ONE) * tile).as_vec2();
        Vec4::new(
            2.0 * lo.x / size.x - 1.0,
            2.0 * hi.x / size.x - 1.0,
            1.0 - 2.0 * hi.y / size.y,
            1.0 - 2.0 * lo.y / size.y,
        )
    }

    /// The side planes of the screen rectangle `rect` = `(x0, x1, y0, y1)` in NDC (as
    /// [`tile_ndc`] gives it), from the projection rows (Gribb/Hartmann): through the eye for a
    /// perspective projection, parallel to the view axis for an orthographic one (its last row
    /// is `(0, 0, 0, 1)`).
    pub fn side_planes(projection: Mat4, rect: Vec4) -> SidePlanes {
        let m = projection;
        let row0 = Vec4::new(m.x_axis.x, m.y_axis.x, m.z_axis.x, m.w_axis.x);
        let row1 = Vec4::new(m.x_axis.y, m.y_axis.y, m.z_axis.y, m.w_axis.y);
        let row3 = Vec4::new(m.x_axis.w, m.y_axis.w, m.z_axis.w, m.w_axis.w);
        SidePlanes {
            left: normalized_plane(row0 - rect.x * row3),
            right: normalized_plane(rect.y * row3 - row0),
            bottom: normalized_plane(row1 - rect.z * row3),
            top: normalized_plane(rect.w * row3 - row1),
        }
    }

    /// Whether a view-space sphere clears all six planes: the four sides and the view depths
    /// `near` and `far`.
    pub fn sphere_in_frustum(c: Vec3, r: f32, sides: SidePlanes, near: f32, far: f32) -> bool {
        let mut inside = sides.left.xyz().dot(c) + sides.left.w >= -r;
        inside = inside && sides.right.xyz().dot(c) + sides.right.w >= -r;
        inside = inside && sides.bottom.xyz().dot(c) + sides.bottom.w >= -r;
        inside = inside && sides.top.xyz().dot(c) + sides.top.w >= -r;
        inside = inside && -c.z - near >= -r;
        inside = inside && c.z + far >= -r;
        inside
    }

    /// Half the extent along unit `n` of a box with half-extent axes `x`, `y`, `z`: how far its
    /// corners reach from its centre towards `n`.
    pub fn box_radius_along(x: Vec3, y: Vec3, z: Vec3, n: Vec3) -> f32 {
        n.dot(x).abs() + n.dot(y).abs() + n.dot(z).abs()
    }

    /// Whether a view-space oriented box (centre `c`, half-extent axes `x`, `y`, `z`) clears all
    /// six planes: no plane has all eight corners behind it (the box's extent along each plane's
    /// normal against the centre's distance).
    pub fn box_in_frustum(
        c: Vec3,
        x: Vec3,
        y: Vec3,
        z: Vec3,
        sides: SidePlanes,
        near: f32,
        far: f32,
    ) -> bool {
        let l = sides.left.xyz();
        let r = sides.right.xyz();
        let b = sides.bottom.xyz();
        let t = sides.top.xyz();
        let rz = x.z.abs() + y.z.abs() + z.z.abs();
        let mut inside = l.dot(c) + sides.left.w >= -box_radius_along(x, y, z, l);
        inside = inside && r.dot(c) + sides.right.w >= -box_radius_along(x, y, z, r);
        inside = inside && b.dot(c) + sides.bottom.w >= -box_radius_along(x, y, z, b);
        inside = inside && t.dot(c) + sides.top.w >= -box_radius_along(x, y, z, t);
        inside = inside && -c.z - near >= -rz;
        inside = inside && c.z + far >= -rz;
        inside
    }

    /// Half extents of the view-space axis-aligned box around an oriented box.
    pub fn box_extent(x: Vec3, y: Vec3, z: Vec3) -> Vec3 {
        x.abs() + y.abs() + z.abs()
    }

    /// How much the rays' spread scales at view depth `z`: `z` for rays through the eye, 1 for
    /// parallel rays.
    pub fn ray_scale(rays: TileRays, z: f32) -> f32 {
        let mut s = z;
        if rays.parallel != 0u32 {
            s = 1.0;
        }
        s
    }

    /// Whether the axis-aligned box at `c` with half extents `e` overlaps the view-space
    /// bounding box of the rectangle's frustum between view depths `zn` and `zf`.
    pub fn box_reaches_box(c: Vec3, e: Vec3, rays: TileRays, zn: f32, zf: f32) -> bool {
        let sn = ray_scale(rays, zn);
        let sf = ray_scale(rays, zf);
        let lo = (rays.min * sn).min(rays.min * sf).extend(-zf);
        let hi = (rays.max * sn).max(rays.max * sf).extend(-zn);
        let gap = (lo - (c + e)).max((c - e) - hi);
        gap.x <= 0.0 && gap.y <= 0.0 && gap.z <= 0.0
    }

    /// View-space direction through NDC `(x, y)`, scaled to view depth 1; with `parallel`
    /// non-zero (an orthographic projection), the ray's view-space `xy`, the same at every depth.
    pub fn view_ray(inv_projection: Mat4, parallel: u32, x: f32, y: f32) -> Vec2 {
        let p = inv_projection * Vec4::new(x, y, 0.5, 1.0);
        let v = p.xyz() / p.w;
        let mut ray = v.xy();
        if parallel == 0u32 {
            ray = v.xy() / -v.z;
        }
        ray
    }

    /// The corner rays of the screen rectangle `rect` = `(x0, x1, y0, y1)` in NDC (a perspective
    /// projection maps NDC `x` to view `x / −z` alone, and `y` likewise, so two corners do; an
    /// orthographic one, `orthographic` non-zero, maps NDC `x` to view `x` alone).
    pub fn tile_rays(inv_projection: Mat4, orthographic: u32, rect: Vec4) -> TileRays {
        let a = view_ray(inv_projection, orthographic, rect.x, rect.z);
        let b = view_ray(inv_projection, orthographic, rect.y, rect.w);
        TileRays {
            min: a.min(b),
            max: a.max(b),
            parallel: orthographic,
        }
    }

    /// Whether a view-space sphere reaches the view-space bounding box of the rectangle's
    /// frustum between view depths `zn` and `zf` (the box's closest point within the radius).
    pub fn sphere_reaches_box(c: Vec3, r: f32, rays: TileRays, zn: f32, zf: f32) -> bool {
        let sn = ray_scale(rays, zn);
        let sf = ray_scale(rays, zf);
        let lo = (rays.min * sn).min(rays.min * sf);
        let hi = (rays.max * sn).max(rays.max * sf);
        let closest = c.clamp(lo.extend(-zf), hi.extend(-zn));
        (c - closest).length_squared() <= r * r
    }

    /// The 2.5D mask cell of view depth `d` in a tile's range `[near, far]` (clamped).
    pub fn mask_cell(d: f32, near: f32, far: f32) -> u32 {
        let span = far - near;
        let mut cell = 0u32;
        if span > 0.0 {
            let t = ((d - near) / span * MASK_CELLS as f32).floor().max(0.0);
            cell = (t as u32).min(MASK_CELLS - 1u32);
        }
        cell
    }
}
