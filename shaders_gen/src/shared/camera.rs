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
        /// Where view vectors point, homogeneous: `(eye, 1)` for a perspective camera, the
        /// view's +Z axis in world space with `w` 0 for an orthographic one (parallel view
        /// rays); the unit view vector at `p` is `normalize(xyz − p w)`.
        pub eye_homogeneous: Vec4,
    }

    /// Per-draw transforms.
    pub struct Draw {
        pub world_from_mesh: Mat4,
        /// Inverse transpose of `world_from_mesh` (normals).
        pub normal_from_mesh: Mat4,
        /// Material index.
        pub material: u32,
        /// Sign of `world_from_mesh`'s determinant: -1 where the draw is mirrored (glTF: its
        /// front faces wind clockwise; the bitangent, `cross(normal, tangent) * tangent.w`,
        /// flips with it), else 1.
        pub handedness: f32,
    }

    /// Clip position of a mesh-space position: world-from-mesh first, then view-projection.
    pub fn clip_position(view_projection: Mat4, world_from_mesh: Mat4, position: Vec3) -> Vec4 {
        view_projection * (world_from_mesh * position.extend(1.0))
    }
}
