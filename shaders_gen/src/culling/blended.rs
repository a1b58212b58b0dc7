//! The blended draws of a view, back to front on the GPU: their sort keys, then (after the
//! `particle_sort` bitonic sort) their indirect arguments in that order.

/// Blended draws back to front, for one multi-draw.
///
/// The host keeps every blended draw's `DrawIndexedIndirect` arguments in `TEMPLATES` (five
/// words, instance count 1, first instance = the draw's index in the `view` library's
/// `DRAWS`), in ascending draw order. Each frame `blended_keys` writes one `(key, position)`
/// pair per template into `KEYS` (padded to the sort's power of two): the key orders the draws
/// back to front by the farness of their box's centre from the eye (as
/// `renderer::frame_data::farness`: squared distance from a perspective eye, depth along an
/// orthographic camera's rays), and a draw outside the frustum, one whose box is empty (a
/// removed instance) and the padding get `HIDDEN`, which sorts last. `particle_sort` sorts the
/// pairs ascending by key then position, so ties keep draw order. `blended_args` then writes
/// position `i`'s arguments: the template of the `i`-th pair, its instance count 0 where the
/// pair is hidden.
///
/// The frustum test is the `box_frustum` library's, with a slack of 1e-4 of each box's
/// diagonal (`renderer`'s CPU order uses the same rule).
#[shader_dsl::shader(uses(crate::shared::box_frustum))]
pub mod blended_order {
    pub const WORKGROUP: u32 = 64;
    /// The key of a pair that draws nothing.
    pub const HIDDEN: u32 = 0xFFFF_FFFF;

    /// The view and the draw counts.
    pub struct BlendedParams {
        pub frustum: Frustum,
        /// `(eye, 1)` for a perspective camera; the view's +Z axis, `w` 0, for an
        /// orthographic one.
        pub eye_homogeneous: Vec4,
        /// Blended draws (`TEMPLATES` entries).
        pub count: u32,
        /// Pairs in `KEYS` (a power of two, at least `count`).
        pub padded: u32,
        /// 1: draws outside the frustum are hidden; 0: every draw is kept.
        pub cull: u32,
        pub pad: u32,
    }

    #[uniform(group = 0, binding = 0)]
    static PARAMS: BlendedParams;
    #[storage(group = 0, binding = 1)]
    static BOXES: [DrawBox];
    #[storage(group = 0, binding = 2)]
    static TEMPLATES: [u32];
    #[storage(group = 0, binding = 3, read_write)]
    static KEYS: [UVec2];
    #[storage(group = 0, binding = 4, read_write)]
    static ARGS: [u32];

    /// `x` as an unsigned integer of the same order (negative values below positive ones).
    fn ordered_bits(x: f32) -> u32 {
        let bits = x.to_bits();
        select(
            (bits & 0x8000_0000u32) != 0u32,
            !bits,
            bits | 0x8000_0000u32,
        )
    }

    /// How far `p` is from the eye, in the order blended draws are drawn (farthest first).
    fn farness(eye: Vec4, p: Vec3) -> f32 {
        let mut f = 0.0;
        if eye.w == 0.0 {
            f = -p.dot(eye.xyz());
        } else {
            let d = p - eye.xyz() / eye.w;
            f = d.dot(d);
        }
        f
    }

    /// Pair `i`: the `i`-th blended draw's key, or `HIDDEN`.
    #[compute(workgroup_size(64, 1, 1))]
    pub fn blended_keys(#[builtin(global_invocation_id)] gid: UVec3) {
        let i = gid.x;
        if i < PARAMS.padded {
            let mut key = HIDDEN;
            if i < PARAMS.count {
                let b = BOXES[TEMPLATES[i * 5u32 + 4u32]];
                let extent = b.max.xyz() - b.min.xyz();
                let empty = extent.x < 0.0 || extent.y < 0.0 || extent.z < 0.0;
                let slack = 1e-4 * extent.length();
                let seen = PARAMS.cull == 0u32 || draw_in_frustum(PARAMS.frustum, b, slack);
                if !empty && seen {
                    let centre = (b.min.xyz() + b.max.xyz()) * 0.5;
                    // Farthest first: the complement of the farness's order.
                    key = !ordered_bits(farness(PARAMS.eye_homogeneous, centre));
                }
            }
            KEYS[i] = UVec2::new(key, i);
        }
    }

    /// Position `i`'s arguments after the sort.
    #[compute(workgroup_size(64, 1, 1))]
    pub fn blended_args(#[builtin(global_invocation_id)] gid: UVec3) {
        let i = gid.x;
        if i < PARAMS.count {
            let pair = KEYS[i];
            let from = pair.y * 5u32;
            let at = i * 5u32;
            ARGS[at] = TEMPLATES[from];
            ARGS[at + 1u32] = select(pair.x == HIDDEN, 0u32, 1u32);
            ARGS[at + 2u32] = TEMPLATES[from + 2u32];
            ARGS[at + 3u32] = TEMPLATES[from + 3u32];
            ARGS[at + 4u32] = TEMPLATES[from + 4u32];
        }
    }
}
