//! The depth pre-pass (pre-Z).

/// Depth pre-pass: transforms positions to clip space and writes depth only (no fragment
/// stage, no colour target).
///
/// The group 0 `Camera` has the same layout as `forward`'s, so one buffer serves both passes.
/// Alpha-masked materials are not handled here: the DSL has no `discard` (see the module
/// report), so a masked material cannot reject texels in a fragment stage.
#[shader_dsl::shader]
pub mod prez {
    /// The camera, shared with the forward pass.
    pub struct Camera {
        pub view: Mat4,
        pub projection: Mat4,
        pub view_projection: Mat4,
        /// Eye position in world space.
        pub eye: Vec3,
    }

    /// Per-draw transforms.
    pub struct Draw {
        pub world_from_mesh: Mat4,
        /// Inverse transpose of `world_from_mesh` (normals).
        pub normal_from_mesh: Mat4,
        /// Material index (for the renderer's bookkeeping).
        pub material: u32,
    }

    #[uniform(group = 0, binding = 0)]
    static CAMERA: Camera;
    #[uniform(group = 1, binding = 0)]
    static DRAW: Draw;

    #[vertex]
    pub fn vs_prez(#[location(0)] position: Vec3, #[location(1)] uv: Vec2) -> Vec4 {
        let _ = uv;
        let world = DRAW.world_from_mesh * position.extend(1.0);
        CAMERA.view_projection * world
    }
}
