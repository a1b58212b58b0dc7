//! The scene's geometry as compute and vertex-pulling shaders read it: the shared index and
//! vertex streams as storage, and the per-draw record that places a draw in them.

/// The shared geometry of the scene, read by index rather than through vertex buffers.
///
/// A scene triangle's ID is `DRAW_GEOMETRY[d].first_triangle + t + 1` for triangle `t` of draw
/// `d`, 0 being no triangle (sky): draws number their triangles one after another in draw
/// order, so IDs are unique across the scene's instances and fit 32 bits while the scene has
/// fewer than 2³² − 1 drawn triangles. `triangle_of` finds the draw of an ID by binary search
/// over `first_triangle`, which rises with the draw index, within the draws the ID's block of
/// `2^TRIANGLE_BLOCK_SHIFT` IDs spans: after its `draws` records, `DRAW_GEOMETRY` holds one
/// record a block (and one past the last), whose `first_index` is the last draw whose first
/// triangle is at or before the block's first (the **triangle directory**). On the city of
/// 20,000 instances that is two or three steps where a search over every draw took fifteen.
///
/// The streams are the scene's vertex buffers (`POSITION` and `NORMAL` three floats a vertex,
/// `TEXCOORD_n` two, `COLOR_0` and `TANGENT` four) and its `u32` index buffer; a draw's index
/// `i` names vertex `SCENE_INDICES[first_index + i] + base_vertex`.
#[shader_dsl::library]
pub mod vis_geometry {
    /// Where a draw's triangles are.
    pub struct DrawGeometry {
        /// Its first index in `SCENE_INDICES`.
        pub first_index: u32,
        /// Added to each of its indices.
        pub base_vertex: u32,
        /// Its first triangle's ID, less one.
        pub first_triangle: u32,
        /// Its triangles.
        pub triangle_count: u32,
    }

    /// `triangle_of`'s directory has a record for every `1 << TRIANGLE_BLOCK_SHIFT` triangle
    /// IDs.
    pub const TRIANGLE_BLOCK_SHIFT: u32 = 8;

    /// A triangle of the scene: its draw, and its three vertices.
    pub struct SceneTriangle {
        pub draw: u32,
        pub vertices: UVec3,
    }

    /// Per draw, in draw order; then the triangle directory (see the module).
    #[storage(group = 3, binding = 0)]
    static DRAW_GEOMETRY: [DrawGeometry];
    #[storage(group = 3, binding = 1)]
    static SCENE_INDICES: [u32];
    #[storage(group = 3, binding = 2)]
    static POSITIONS: [f32];
    #[storage(group = 3, binding = 3)]
    static NORMALS: [f32];
    #[storage(group = 3, binding = 4)]
    static TANGENTS: [Vec4];
    #[storage(group = 3, binding = 5)]
    static UV0: [Vec2];
    #[storage(group = 3, binding = 6)]
    static UV1: [Vec2];
    #[storage(group = 3, binding = 7)]
    static COLORS: [Vec4];

    /// Vertex `v`'s mesh-space position.
    pub fn vertex_position(v: u32) -> Vec3 {
        Vec3::new(
            POSITIONS[3u32 * v],
            POSITIONS[3u32 * v + 1u32],
            POSITIONS[3u32 * v + 2u32],
        )
    }

    /// Vertex `v`'s mesh-space normal.
    pub fn vertex_normal(v: u32) -> Vec3 {
        Vec3::new(
            NORMALS[3u32 * v],
            NORMALS[3u32 * v + 1u32],
            NORMALS[3u32 * v + 2u32],
        )
    }

    /// A vertex a raster pass pulls from storage, and its triangle's ID.
    pub struct PulledVertex {
        /// The vertex (index into the streams).
        pub vertex: u32,
        /// Its triangle's ID.
        pub triangle: u32,
    }

    /// The vertex of draw `draw` that a raster pass drawing the draw's indirect arguments over
    /// a *sequence* index buffer (index `i` is `i`) sees as `index` (its `vertex_index`):
    /// `index − base_vertex` is the position in `SCENE_INDICES`, so the vertex knows its
    /// triangle without `primitive_index` (which WebGPU lacks).
    pub fn pulled_vertex(index: u32, draw: u32) -> PulledVertex {
        let g = DRAW_GEOMETRY[draw];
        let at = index - g.base_vertex;
        PulledVertex {
            vertex: SCENE_INDICES[at] + g.base_vertex,
            triangle: g.first_triangle + (at - g.first_index) / 3u32 + 1u32,
        }
    }

    /// Vertex `k` (0, 1 or 2) of triangle `t` of draw `d`.
    pub fn triangle_vertex(d: u32, t: u32, k: u32) -> u32 {
        let g = DRAW_GEOMETRY[d];
        SCENE_INDICES[g.first_index + 3u32 * t + k] + g.base_vertex
    }

    /// The draw and vertices of the triangle with ID `id` (not 0), among `draws` draws.
    pub fn triangle_of(id: u32, draws: u32) -> SceneTriangle {
        let target = id - 1u32;
        // The last draw whose first triangle is at or before `target`: at or after the one of
        // its block's first triangle, at or before the one of the next block's.
        let block = draws + (target >> TRIANGLE_BLOCK_SHIFT);
        let mut lo = DRAW_GEOMETRY[block].first_index;
        let mut hi = (DRAW_GEOMETRY[block + 1u32].first_index + 1u32).min(draws);
        while hi - lo > 1u32 {
            let mid = (lo + hi) / 2u32;
            if DRAW_GEOMETRY[mid].first_triangle <= target {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let t = target - DRAW_GEOMETRY[lo].first_triangle;
        SceneTriangle {
            draw: lo,
            vertices: UVec3::new(
                triangle_vertex(lo, t, 0u32),
                triangle_vertex(lo, t, 1u32),
                triangle_vertex(lo, t, 2u32),
            ),
        }
    }
}
