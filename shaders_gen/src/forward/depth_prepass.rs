//! The depth pre-pass (pre-Z).

/// Depth pre-pass: transforms positions to clip space and writes depth only (no fragment
/// stage, no colour target).
///
/// `Camera` and `Draw` come from the `view` library, like `forward`'s, so one buffer serves both
/// passes, and the clip position is the library's `clip_position`, also like `forward`'s; the
/// position output is `#[invariant]`, so the forward pass's `LessEqual` test against this
/// depth sees bit-identical values.
/// Alpha-masked materials are not handled here: the DSL has no `discard` (see the module
/// report), so a masked material cannot reject texels in a fragment stage.
#[shader_dsl::shader(
    axes(alpha_mask: bool = [false, true] => "mask"),
    uses(crate::shared::view),
)]
pub mod prez {
    /// What the masked variant needs of a material.
    pub struct MaskMaterial {
        pub base_color: Vec4,
        pub alpha_cutoff: f32,
    }

    pub struct VsOut {
        #[builtin(position)]
        #[invariant]
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
        VsOut {
            clip: clip_position(CAMERA.view_projection, DRAW.world_from_mesh, position),
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
