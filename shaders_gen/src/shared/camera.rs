//! The camera and per-draw transforms of the geometry passes, and their one clip-position
//! computation.

/// `Camera` and `Draw` (one layout for the depth pre-pass and the forward pass, so one buffer
/// serves both) and `clip_position`, which both passes call, so the pre-pass depth and the
/// forward pass's depth come from the very same arithmetic (see `#[invariant]` on their
/// position outputs).
#[shader_dsl::library]
pub mod view {
    /// The camera of a frame.
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
        /// Material index.
        pub material: u32,
    }

    /// Clip position of a mesh-space position: world-from-mesh first, then view-projection.
    pub fn clip_position(view_projection: Mat4, world_from_mesh: Mat4, position: Vec3) -> Vec4 {
        view_projection * (world_from_mesh * position.extend(1.0))
    }
}
