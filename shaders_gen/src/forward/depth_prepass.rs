//! The depth pre-pass (pre-Z).

/// Depth pre-pass: transforms positions to clip space and writes depth only (no fragment
/// stage, no colour target).
///
/// The group 0 `Camera` has the same layout as `forward`'s, so one buffer serves both passes.
/// Alpha-masked materials are not handled here: the DSL has no `discard` (see the module
/// report), so a masked material cannot reject texels in a fragment stage.
#[shader_dsl::shader(axes(alpha_mask: bool = [false, true] => "mask"))]
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

    /// What the masked variant needs of a material.
    pub struct MaskMaterial {
        pub base_color: Vec4,
        pub alpha_cutoff: f32,
    }

    pub struct VsOut {
        #[builtin(position)]
        pub clip: Vec4,
        #[location(0)]
        pub uv: Vec2,
    }

    #[uniform(group = 0, binding = 0)]
    static CAMERA: Camera;
    #[uniform(group = 1, binding = 0)]
    static DRAW: Draw;
    #[uniform(group = 2, binding = 0)]
    #[when(alpha_mask)]
    static MASK: MaskMaterial;
    #[texture(group = 2, binding = 1)]
    #[when(alpha_mask)]
    static BASE_COLOR_TEX: Texture2d<f32>;
    #[sampler(group = 2, binding = 2)]
    #[when(alpha_mask)]
    static MASK_SAMPLER: Sampler;

    #[vertex]
    pub fn vs_prez(#[location(0)] position: Vec3, #[location(1)] uv: Vec2) -> VsOut {
        let world = DRAW.world_from_mesh * position.extend(1.0);
        VsOut {
            clip: CAMERA.view_projection * world,
            uv,
        }
    }

    /// Masked materials: texels below the cutoff leave no depth.
    #[fragment]
    pub fn fs_prez_mask(input: VsOut) {
        if alpha_mask {
            let alpha = MASK.base_color.w * BASE_COLOR_TEX.sample(MASK_SAMPLER, input.uv).w;
            if alpha < MASK.alpha_cutoff {
                discard();
            }
        }
    }
}
