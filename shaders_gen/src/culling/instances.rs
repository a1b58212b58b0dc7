//! Culling the scene's draws on the GPU: each draw's world box against a view's frustum,
//! written straight into the indirect arguments the geometry passes draw with.

/// Frustum culling of the scene's draws for the main view.
///
/// The host lays the view's draws out in slots, grouped into batches that share a pipeline and
/// a material (one multi-draw each), and writes every slot's `DrawIndexedIndirect` arguments
/// once (five words: index count, instance count, first index, base vertex, first instance =
/// the draw's index in the `view` library's `DRAWS`). Each frame, `cull_frustum` sets a slot's
/// instance count to 1 where the draw's world box (`BOXES`, rewritten when an instance moves)
/// meets the frustum (and, in the first phase of occlusion culling, was visible last frame),
/// else 0, and counts the slots drawn in `VISIBLE[0]`, and in `VISIBLE[1]` too when no second
/// phase follows (`occlusion_cull` counts both phases' there), so `VISIBLE[1]` is always the
/// frame's drawn count.
///
/// The box test is the `box_frustum` library's. A slot holding `NO_DRAW` (a batch's spare
/// slot, kept for instances an engine adds) draws nothing.
#[shader_dsl::shader(uses(crate::shared::box_frustum))]
pub mod instance_cull {
    pub const WORKGROUP: u32 = 64;
    /// A slot without a draw.
    pub const NO_DRAW: u32 = 0xFFFF_FFFF;

    /// One view's frustum and the slot count.
    pub struct CullParams {
        pub frustum: Frustum,
        /// Slots to cull (entries of `SLOT_DRAWS`).
        pub slot_count: u32,
        /// How far outside a plane a box may reach and still be kept, in world units.
        pub slack: f32,
        /// 1: the first phase of occlusion culling, which draws only the slots `HISTORY` marks
        /// visible last frame (`occlusion_cull` tests the rest); 0: every slot in the frustum.
        pub use_history: u32,
        pub pad1: u32,
    }

    #[uniform(group = 0, binding = 0)]
    static PARAMS: CullParams;
    #[storage(group = 0, binding = 1)]
    static BOXES: [DrawBox];
    #[storage(group = 0, binding = 2)]
    static SLOT_DRAWS: [u32];
    #[storage(group = 0, binding = 3, read_write)]
    static ARGS: [u32];
    #[storage(group = 0, binding = 4, read_write)]
    static VISIBLE: [Atomic<u32>];
    #[storage(group = 0, binding = 5)]
    static HISTORY: [u32];

    /// One slot: its draw's box against the frustum, into its instance count.
    #[compute(workgroup_size(64, 1, 1))]
    pub fn cull_frustum(#[builtin(global_invocation_id)] gid: UVec3) {
        let slot = gid.x;
        if slot < PARAMS.slot_count {
            let draw = SLOT_DRAWS[slot];
            let seen = PARAMS.use_history == 0u32 || HISTORY[slot] != 0u32;
            let visible = draw != NO_DRAW
                && seen
                && draw_in_frustum(PARAMS.frustum, BOXES[draw], PARAMS.slack);
            ARGS[slot * 5u32 + 1u32] = select(visible, 1u32, 0u32);
            if visible {
                VISIBLE[0].fetch_add(1);
                // Without a second phase these are every slot drawn.
                if PARAMS.use_history == 0u32 {
                    VISIBLE[1].fetch_add(1);
                }
            }
        }
    }
}
