//! The compute rasteriser: the visibility raster pass's triangles rasterised by compute kernels
//! into a buffer of 64-bit atomics, one per sample, depth above the triangle ID.

/// Compute rasterisation of the scene's opaque triangles into `VIS64`, one `u64` a sample
/// (`(y × width + x) × msaa + s`), on adapters with `SHADER_INT64_ATOMIC_MIN_MAX`.
///
/// A sample holds `(!depth_bits << 32) | !id`, merged with `fetch_max`: the nearest depth wins,
/// and at equal depth the smallest ID. The buffer is cleared to 0, which no written value is
/// (the complements of a depth in `[0, 1)` and of a 32-bit ID are never both 0), so a sample
/// reads `id = !low` where `high != 0`, and sky where it is 0.
///
/// Each triangle is set up the same way wherever it is rasterised (`raster_triangle`): its
/// vertices' clip positions from `view`'s `clip_position`, as the hardware raster's, and the
/// adjugate of their `(x, y, w)` matrix, whose rows are the three edge functions in
/// normalised device coordinates. This is 2D homogeneous rasterisation: it needs no clipping,
/// since a triangle that crosses the eye plane still has correct edge functions (a point is
/// inside where all three have the sign of the determinant, which also puts it in front of
/// the eye), and its NDC depth is a plane, `dot(z_plane, (x, y, 1))`, because the edge
/// functions weighted by the vertices' `w` sum to the determinant. A sample exactly on an edge
/// belongs to one of the two triangles that share it, as on the hardware: each computes the
/// edge's function from its lower-numbered vertex (so both get the same bits, FMA contraction
/// or not), one negates it exactly, and `owns_edge` applies the top-left rule.
///
/// Like the hardware raster, it culls back faces where the draw's batch does (its class,
/// `CLASSES`), drops depth outside `[0, 1)`, samples at the standard positions
/// (`sample_pattern`), leaves masked and blended draws (class 0) to the hardware raster, and
/// draws only the slots scene culling kept: a class holds its draw's slot, whose instance
/// count in the half's `SLOT_ARGS` is 0 where culling left it out (under occlusion culling it
/// runs once a half, the second over the first's samples).
///
/// `raster_triangles` takes a chunk a workgroup (`CHUNKS`, listed by the host: up to
/// `TRIANGLE_WORKGROUP` triangles of one draw; a culled draw's chunk ends after three loads),
/// an invocation a triangle. It rasterises a triangle whose pixel box covers at most
/// `small_area` pixels itself, and lists a larger one (or one crossing the eye plane, whose box
/// is the screen) in `LARGE`, set up, with an `ITEMS` entry per 16×16 tile of its box (written
/// by the whole workgroup, empty where the tile lies outside an edge). `tile_args` writes the
/// indirect dispatch of `raster_tiles`, a workgroup an item, an invocation a pixel. Triangles
/// past `LARGE`'s or `ITEMS`' capacity are counted in `COUNTERS[OVERFLOW]` and their items made
/// empty, so nothing stale is drawn and the host can report what was left out.
#[shader_dsl::shader(
    axes(msaa: u32 = [1, 2, 4, 8] => "msaa"),
    uses(
        crate::shared::view,
        crate::shared::sample_pattern,
        crate::visibility::geometry::vis_geometry,
    ),
)]
pub mod vis_compute_raster {
    /// Invocations of `raster_triangles`' workgroups, and triangles of a chunk at most.
    pub const TRIANGLE_WORKGROUP: u32 = 64;
    /// Side of a large triangle's tiles, in pixels (`raster_tiles`' workgroup).
    pub const TILE: u32 = 16;
    /// Workgroups in a row of the tiles' and chunks' dispatches (`x + y × TILE_ROW`).
    pub const TILE_ROW: u32 = 32768;
    /// A draw's class: rasterised here.
    pub const RASTERISE: u32 = 1;
    /// A draw's class: both faces drawn.
    pub const DOUBLE_SIDED: u32 = 2;
    /// A draw's class: front faces wind clockwise (a mirrored instance's batch).
    pub const MIRRORED: u32 = 4;
    /// A draw's class holds its batch slot above these bits.
    pub const SLOT_SHIFT: u32 = 3;
    /// `COUNTERS[LARGE_COUNT]`: triangles listed in `LARGE` (past the capacity too).
    pub const LARGE_COUNT: u32 = 0;
    /// `COUNTERS[ITEM_COUNT]`: tiles listed in `ITEMS` (past the capacity too).
    pub const ITEM_COUNT: u32 = 1;
    /// `COUNTERS[OVERFLOW]`: large triangles left out, `LARGE` or `ITEMS` being full.
    pub const OVERFLOW: u32 = 2;
    /// `TILE_ARGS[LATE_ARGS..]`: the late half's `raster_triangles` dispatch.
    pub const LATE_ARGS: u32 = 4;
    /// An `ITEMS` entry that rasterises nothing.
    pub const NO_ITEM: u32 = 0xFFFF_FFFF;

    /// One frame's rasterisation.
    pub struct RasterParams {
        pub width: u32,
        pub height: u32,
        /// Entries of `CHUNKS`.
        pub chunks: u32,
        /// The largest pixel box one invocation rasterises (larger: by tiles).
        pub small_area: u32,
        /// Entries of `LARGE`.
        pub large_capacity: u32,
        /// Entries of `ITEMS`.
        pub item_capacity: u32,
        /// 1: every draw with a class, whatever `SLOT_ARGS` says; 0: the slots with an instance.
        pub every_slot: u32,
        pub pad: u32,
    }

    /// A large triangle as `raster_triangles` set it up, for its tiles.
    pub struct LargeTriangle {
        pub e0: Vec3,
        pub id: u32,
        pub e1: Vec3,
        /// Tile columns of its box.
        pub columns: u32,
        pub e2: Vec3,
        /// Its box's first tile column and row, `x | y << 16`.
        pub first_tile: u32,
        pub z_plane: Vec3,
        pub pad: u32,
        pub lo: UVec2,
        pub hi: UVec2,
    }

    /// A large triangle of one `raster_triangles` workgroup whose tiles the workgroup lists
    /// together.
    pub struct TileListing {
        pub e0: Vec3,
        /// Its `LARGE` entry; `NO_ITEM` where it did not fit (its items are made empty).
        pub large: u32,
        pub e1: Vec3,
        /// Its first `ITEMS` entry.
        pub base: u32,
        pub e2: Vec3,
        /// Tiles of its box (0: no large triangle).
        pub count: u32,
        /// Its box's first tile column and row, `x | y << 16`.
        pub first_tile: u32,
        /// Tile columns of its box.
        pub columns: u32,
        pub pad: UVec2,
    }

    /// A triangle set up for rasterisation.
    pub struct RasterTriangle {
        /// Edge functions over NDC `(x, y, 1)`, positive inside.
        pub e0: Vec3,
        pub e1: Vec3,
        pub e2: Vec3,
        /// NDC depth over `(x, y, 1)`.
        pub z_plane: Vec3,
        /// Its pixel box, inclusive, on the screen.
        pub lo: UVec2,
        pub hi: UVec2,
        /// Whether it draws anything: its draw is rasterised here, it is not a culled back
        /// face, not degenerate, and not wholly outside one frustum plane.
        pub drawn: bool,
        /// All three vertices in front of the eye (its box is its own, not the screen).
        pub in_front: bool,
    }

    #[uniform(group = 0, binding = 0)]
    static CAMERA: Camera;
    #[uniform(group = 0, binding = 1)]
    static PARAMS: RasterParams;
    /// Per draw (as `DRAW_GEOMETRY`): `RASTERISE | DOUBLE_SIDED | MIRRORED` bits and the
    /// draw's slot `<< SLOT_SHIFT`; 0 for the draws the hardware raster draws (masked) or
    /// nothing draws (blended, hidden).
    #[storage(group = 0, binding = 2)]
    static CLASSES: [u32];
    /// The half's indirect draw arguments, five a slot: the second, the instance count, is 0
    /// where scene culling left the slot out.
    #[storage(group = 0, binding = 8)]
    static SLOT_ARGS: [u32];
    /// `raster_triangles`' work: per chunk, its draw (one with a class) and its first
    /// triangle in the draw; a chunk is the draw's next `TRIANGLE_WORKGROUP` triangles, or the
    /// rest.
    #[storage(group = 0, binding = 9)]
    static CHUNKS: [UVec2];
    #[storage(group = 0, binding = 3, read_write)]
    static VIS64: [Atomic<u64>];
    #[storage(group = 0, binding = 4, read_write)]
    static COUNTERS: [Atomic<u32>];
    /// The large triangles of a `raster_triangles` workgroup, one an invocation.
    #[workgroup]
    static LISTINGS: [TileListing; TRIANGLE_WORKGROUP];
    /// Large triangles, set up once for all their tiles.
    #[storage(group = 0, binding = 5, read_write)]
    static LARGE: [LargeTriangle];
    /// One a tile of a large triangle: its `LARGE` entry and the tile's number in its box.
    #[storage(group = 0, binding = 6, read_write)]
    static ITEMS: [UVec2];
    /// Indirect dispatches: `raster_tiles`' in words 0 to 2; under occlusion culling, the late
    /// half's `raster_triangles`' in words `LATE_ARGS..LATE_ARGS + 3`.
    #[storage(group = 0, binding = 7, read_write)]
    static TILE_ARGS: [u32];
    /// Occlusion culling's slots drawn by its first phase and by either (the late half's).
    #[storage(group = 0, binding = 10)]
    static DRAWN: [u32];

    /// Whether the sample at `at` = NDC `(x, y, 1)` is inside edge `e`. On the edge, the
    /// top-left rule of Vulkan and D3D: a left edge (the inside to its right, `e.x > 0`) or a
    /// top edge (horizontal, the inside below it: `e.y < 0`, NDC's y being up) owns it.
    fn owns_edge(e: Vec3, at: Vec3) -> bool {
        let d = e.dot(at);
        d > 0.0 || (d == 0.0 && (e.x > 0.0 || (e.x == 0.0 && e.y < 0.0)))
    }

    /// Whether edge `e` (NDC `(x, y, 1)`, positive inside) may be non-negative somewhere in
    /// the pixel rectangle `lo..hi`: its largest value there, at a corner, is not below 0 by
    /// more than rounding (a sample inside the rectangle is never judged outside).
    fn edge_reaches(e: Vec3, lo: Vec2, hi: Vec2) -> bool {
        let size = Vec2::new(PARAMS.width as f32, PARAMS.height as f32);
        let x = Vec2::new(lo.x, hi.x) / size.x * 2.0 - Vec2::ONE;
        let y = Vec2::ONE - Vec2::new(lo.y, hi.y) / size.y * 2.0;
        let largest = e.z + (e.x * x.x).max(e.x * x.y) + (e.y * y.x).max(e.y * y.y);
        largest >= -1.0e-5 * (e.x.abs() + e.y.abs() + e.z.abs())
    }

    /// Whether tile `j` of `l`'s box may hold a sample of its triangle (inside all three
    /// edges somewhere): the tiles that cannot are listed empty.
    fn tile_touches(l: TileListing, j: u32) -> bool {
        let first = UVec2::new(l.first_tile & 0xFFFFu32, l.first_tile >> 16u32);
        let tile = first + UVec2::new(j % l.columns, j / l.columns);
        let lo = (tile * TILE).as_vec2();
        let hi = lo + Vec2::splat(TILE as f32);
        edge_reaches(l.e0, lo, hi) && edge_reaches(l.e1, lo, hi) && edge_reaches(l.e2, lo, hi)
    }

    /// A clip position's window position, in pixels.
    fn window_of(c: Vec4) -> Vec2 {
        let size = Vec2::new(PARAMS.width as f32, PARAMS.height as f32);
        Vec2::new(c.x / c.w * 0.5 + 0.5, 0.5 - c.y / c.w * 0.5) * size
    }

    /// Whether all three clip positions lie outside one frustum plane.
    fn outside_frustum(c0: Vec4, c1: Vec4, c2: Vec4) -> bool {
        (c0.x > c0.w && c1.x > c1.w && c2.x > c2.w)
            || (c0.x < -c0.w && c1.x < -c1.w && c2.x < -c2.w)
            || (c0.y > c0.w && c1.y > c1.w && c2.y > c2.w)
            || (c0.y < -c0.w && c1.y < -c1.w && c2.y < -c2.w)
            || (c0.z < 0.0 && c1.z < 0.0 && c2.z < 0.0)
            || (c0.z > c0.w && c1.z > c1.w && c2.z > c2.w)
    }

    /// Whether a draw of class `class` is rasterised this half.
    fn class_drawn(class: u32) -> bool {
        let slot = class >> SLOT_SHIFT;
        (class & RASTERISE) != 0u32
            && (PARAMS.every_slot != 0u32 || SLOT_ARGS[slot * 5u32 + 1u32] != 0u32)
    }

    /// Triangle `t` of draw `draw`, of class `class`, set up: the same wherever it is
    /// rasterised.
    pub fn raster_triangle(draw: u32, t: u32, class: u32) -> RasterTriangle {
        let tri = SceneTriangle {
            draw,
            vertices: UVec3::new(
                triangle_vertex(draw, t, 0u32),
                triangle_vertex(draw, t, 1u32),
                triangle_vertex(draw, t, 2u32),
            ),
        };
        let world = DRAWS[tri.draw].world_from_mesh;
        let c0 = clip_position(
            CAMERA.view_projection,
            world,
            vertex_position(tri.vertices.x),
        );
        let c1 = clip_position(
            CAMERA.view_projection,
            world,
            vertex_position(tri.vertices.y),
        );
        let c2 = clip_position(
            CAMERA.view_projection,
            world,
            vertex_position(tri.vertices.z),
        );
        let a0 = Vec3::new(c0.x, c0.y, c0.w);
        let a1 = Vec3::new(c1.x, c1.y, c1.w);
        let a2 = Vec3::new(c2.x, c2.y, c2.w);
        // Each edge from its lower-numbered vertex: the triangles sharing an edge compute the
        // same cross product from the same operands, whatever the compiler fuses, and one of
        // them negates it exactly.
        let v = tri.vertices;
        let e0 = select(v.y < v.z, a1.cross(a2), -a2.cross(a1));
        let e1 = select(v.z < v.x, a2.cross(a0), -a0.cross(a2));
        let e2 = select(v.x < v.y, a0.cross(a1), -a1.cross(a0));
        let det = a0.dot(e0);
        // Counter-clockwise in NDC (y up) has a positive determinant; mirrored batches' front
        // faces wind the other way.
        let front = select((class & MIRRORED) != 0u32, -det, det);
        let culled = (class & DOUBLE_SIDED) == 0u32 && !(front > 0.0);
        let inside = select(det < 0.0, -1.0, 1.0);
        // The depth plane relative to the NDC depth of the vertex nearest the eye plane's far
        // side (largest `w`): `Σ eᵢ wᵢ` is `(0, 0, det)`, so subtracting `z_ref · wᵢ` from
        // each `zᵢ` changes the plane by `(0, 0, z_ref)` exactly, but the sums then add the
        // small depth differences across the triangle instead of cancelling large products
        // (far, small triangles otherwise lost up to 4e-4 of depth in float).
        let mut z_ref = c0.z / c0.w;
        let mut w_max = c0.w;
        if c1.w > w_max {
            z_ref = c1.z / c1.w;
            w_max = c1.w;
        }
        if c2.w > w_max {
            z_ref = c2.z / c2.w;
            w_max = c2.w;
        }
        if !(w_max > 0.0) {
            z_ref = 0.0;
        }
        let relative =
            (e0 * (c0.z - z_ref * c0.w) + e1 * (c1.z - z_ref * c1.w) + e2 * (c2.z - z_ref * c2.w))
                / det;
        let mut out = RasterTriangle {
            e0: e0 * inside,
            e1: e1 * inside,
            e2: e2 * inside,
            z_plane: Vec3::new(relative.x, relative.y, relative.z + z_ref),
            lo: UVec2::ZERO,
            hi: UVec2::new(PARAMS.width - 1u32, PARAMS.height - 1u32),
            drawn: det != 0.0 && !culled && !outside_frustum(c0, c1, c2),
            in_front: c0.w > 0.0 && c1.w > 0.0 && c2.w > 0.0,
        };
        if out.in_front {
            let w0 = window_of(c0);
            let w1 = window_of(c1);
            let w2 = window_of(c2);
            let top = Vec2::new((PARAMS.width - 1u32) as f32, (PARAMS.height - 1u32) as f32);
            let lo = w0.min(w1).min(w2).floor().clamp(Vec2::ZERO, top);
            let hi = w0.max(w1).max(w2).floor().clamp(Vec2::ZERO, top);
            out.lo = lo.as_uvec2();
            out.hi = hi.as_uvec2();
        }
        out
    }

    /// Sample `s` of pixel `p` against triangle `t` (ID `id`): its depth and ID into `VIS64`
    /// where `t` covers it nearer than what is there.
    fn raster_sample(p: UVec2, s: u32, t: RasterTriangle, id: u32) {
        let at = p.as_vec2() + sample_offset(s);
        let ndc = Vec3::new(
            at.x / PARAMS.width as f32 * 2.0 - 1.0,
            1.0 - at.y / PARAMS.height as f32 * 2.0,
            1.0,
        );
        if owns_edge(t.e0, ndc) && owns_edge(t.e1, ndc) && owns_edge(t.e2, ndc) {
            let z = t.z_plane.dot(ndc);
            if z >= 0.0 && z < 1.0 {
                // `& 0x7FFF_FFFF`: -0.0 ranks as 0.0.
                let depth = z.to_bits() & 0x7FFF_FFFFu32;
                let packed = ((!depth as u64) << 32u32) | ((!id) as u64);
                VIS64[(p.y * PARAMS.width + p.x) * msaa + s].fetch_max(packed);
            }
        }
    }

    /// One chunk, an invocation a triangle: small ones rasterised here, large ones listed by
    /// tile, by the whole workgroup (an invocation an item: a triangle across the screen has
    /// thousands), a tile its triangle cannot touch listed empty.
    #[compute(workgroup_size(64, 1, 1))]
    pub fn raster_triangles(
        #[builtin(workgroup_id)] group: UVec3,
        #[builtin(local_invocation_index)] lane: u32,
    ) {
        let chunk = group.x + group.y * TILE_ROW;
        let mut listing = TileListing {
            e0: Vec3::ZERO,
            large: NO_ITEM,
            e1: Vec3::ZERO,
            base: 0u32,
            e2: Vec3::ZERO,
            count: 0u32,
            first_tile: 0u32,
            columns: 1u32,
            pad: UVec2::ZERO,
        };
        let mut class = 0u32;
        let mut draw = 0u32;
        let mut local = 0u32;
        if chunk < PARAMS.chunks {
            let c = CHUNKS[chunk];
            draw = c.x;
            local = c.y + lane;
            class = CLASSES[draw];
        }
        // The same for the whole workgroup: a chunk of a draw not drawn this half ends here.
        if !class_drawn(class) {
            return;
        }
        if local < DRAW_GEOMETRY[draw].triangle_count {
            let id = DRAW_GEOMETRY[draw].first_triangle + local + 1u32;
            let t = raster_triangle(draw, local, class);
            if t.drawn {
                let size = t.hi - t.lo + UVec2::ONE;
                if t.in_front && size.x * size.y <= PARAMS.small_area {
                    for y in t.lo.y..=t.hi.y {
                        for x in t.lo.x..=t.hi.x {
                            for s in 0u32..msaa {
                                raster_sample(UVec2::new(x, y), s, t, id);
                            }
                        }
                    }
                } else {
                    let first = t.lo / TILE;
                    let tiles = t.hi / TILE - first + UVec2::ONE;
                    let count = tiles.x * tiles.y;
                    let k = COUNTERS[LARGE_COUNT].fetch_add(1u32);
                    let base = COUNTERS[ITEM_COUNT].fetch_add(count);
                    // No `base + count`: it could wrap past `u32::MAX`.
                    let fits = k < PARAMS.large_capacity
                        && base < PARAMS.item_capacity
                        && count <= PARAMS.item_capacity - base;
                    let first_tile = first.x | (first.y << 16u32);
                    if fits {
                        LARGE[k] = LargeTriangle {
                            e0: t.e0,
                            id,
                            e1: t.e1,
                            columns: tiles.x,
                            e2: t.e2,
                            first_tile,
                            z_plane: t.z_plane,
                            pad: 0u32,
                            lo: t.lo,
                            hi: t.hi,
                        };
                    } else {
                        COUNTERS[OVERFLOW].fetch_add(1u32);
                    }
                    listing = TileListing {
                        e0: t.e0,
                        large: select(fits, k, NO_ITEM),
                        e1: t.e1,
                        base,
                        e2: t.e2,
                        count,
                        first_tile,
                        columns: tiles.x,
                        pad: UVec2::ZERO,
                    };
                }
            }
        }
        LISTINGS[lane] = listing;
        workgroup_barrier();
        for i in 0u32..TRIANGLE_WORKGROUP {
            let l = LISTINGS[i];
            let mut j = lane;
            while j < l.count {
                if l.base < PARAMS.item_capacity && j < PARAMS.item_capacity - l.base {
                    let mut item = UVec2::new(NO_ITEM, 0u32);
                    if l.large != NO_ITEM && tile_touches(l, j) {
                        item = UVec2::new(l.large, j);
                    }
                    ITEMS[l.base + j] = item;
                }
                j += TRIANGLE_WORKGROUP;
            }
        }
    }

    /// `raster_tiles`' dispatch: one workgroup per listed tile, `TILE_ROW` to a row.
    #[compute(workgroup_size(1, 1, 1))]
    pub fn tile_args() {
        let items = COUNTERS[ITEM_COUNT].load().min(PARAMS.item_capacity);
        TILE_ARGS[0] = items.min(TILE_ROW);
        TILE_ARGS[1] = (items + TILE_ROW - 1u32) / TILE_ROW;
        TILE_ARGS[2] = 1u32;
    }

    /// The late half's `raster_triangles` dispatch: every chunk where occlusion culling's
    /// second phase drew a slot the first did not, none otherwise (a still camera's frames).
    #[compute(workgroup_size(1, 1, 1))]
    pub fn late_triangle_args() {
        let late = DRAWN[1] > DRAWN[0];
        TILE_ARGS[LATE_ARGS] = select(late, PARAMS.chunks.min(TILE_ROW), 0u32);
        TILE_ARGS[LATE_ARGS + 1u32] = (PARAMS.chunks + TILE_ROW - 1u32) / TILE_ROW;
        TILE_ARGS[LATE_ARGS + 2u32] = 1u32;
    }

    /// One tile of one large triangle, an invocation a pixel.
    #[compute(workgroup_size(16, 16, 1))]
    pub fn raster_tiles(
        #[builtin(workgroup_id)] group: UVec3,
        #[builtin(local_invocation_id)] local: UVec3,
    ) {
        let index = group.x + group.y * TILE_ROW;
        let items = COUNTERS[ITEM_COUNT].load().min(PARAMS.item_capacity);
        if index < items {
            let item = ITEMS[index];
            if item.x != NO_ITEM {
                let l = LARGE[item.x];
                let t = RasterTriangle {
                    e0: l.e0,
                    e1: l.e1,
                    e2: l.e2,
                    z_plane: l.z_plane,
                    lo: l.lo,
                    hi: l.hi,
                    drawn: true,
                    in_front: true,
                };
                let first = UVec2::new(l.first_tile & 0xFFFFu32, l.first_tile >> 16u32);
                let tile = first + UVec2::new(item.y % l.columns, item.y / l.columns);
                let p = tile * TILE + local.xy();
                if p.x >= t.lo.x && p.x <= t.hi.x && p.y >= t.lo.y && p.y <= t.hi.y {
                    for s in 0u32..msaa {
                        raster_sample(p, s, t, l.id);
                    }
                }
            }
        }
    }
}
