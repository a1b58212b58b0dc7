//! The camera and per-draw transforms of the geometry passes, and their one clip-position
//! computation.

/// `Camera`, the scene's draw records `DRAWS` (group 1, one storage buffer of every draw of the
/// scene, read by the pre-Z, forward, G-buffer and shadow-caster programs alike, so one bind
/// group serves every pass), and `clip_position`, which every geometry pass calls, so the
/// pre-pass depth and the forward pass's depth come from the very same arithmetic (see
/// `#[invariant]` on their position outputs).
///
/// A draw finds its record by its instance index: the renderer draws draw `d` as instance
/// `d..d + 1` (`first_instance` = `d`), so no per-draw bind group exists.
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

    /// One draw's record: a primitive of a scene instance, where it is and what it is made of.
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

    /// Every draw of the scene, indexed by the draw's instance index.
    #[storage(group = 1, binding = 0)]
    static DRAWS: [Draw];

    /// Clip position of a mesh-space position: world-from-mesh first, then view-projection.
    pub fn clip_position(view_projection: Mat4, world_from_mesh: Mat4, position: Vec3) -> Vec4 {
        view_projection * (world_from_mesh * position.extend(1.0))
    }
}
