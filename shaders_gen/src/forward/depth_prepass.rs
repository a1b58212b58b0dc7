//! The depth pre-pass (pre-Z).

/// Depth pre-pass: transforms positions to clip space and writes depth only (no colour target;
/// no fragment stage for opaque materials).
///
/// `Camera` and the draw records `DRAWS` come from the `view` library, like `forward`'s, so one
/// buffer serves both passes, and the clip position is the library's `clip_position`, also like `forward`'s; the
/// position output is `#[invariant]`, so the forward pass's `LessEqual` test against this
/// depth sees bit-identical values.
///
/// Alpha-masked materials (`alpha_mask`) draw with `vs_prez_mask` and `fs_prez_mask`: the
/// fragment discards texels whose alpha (base colour factor × base colour texture, read with
/// its own UV set and transform, × vertex colour alpha) is below the cutoff, as the forward
/// shading does.
#[shader_dsl::shader(
    axes(alpha_mask: bool = [false, true] => "mask"),
    uses(crate::shared::view, crate::shared::material_uv, crate::shared::material_table),
)]
pub mod prez {
    pub struct VsOut {
        #[builtin(position)]
        #[invariant]
        pub clip: Vec4,
    }

    #[uniform(group = 0, binding = 0)]
    static CAMERA: Camera;

    #[vertex]
    pub fn vs_prez(#[location(0)] position: Vec3, #[builtin(instance_index)] draw: u32) -> VsOut {
        VsOut {
            clip: clip_position(
                CAMERA.view_projection,
                DRAWS[draw].world_from_mesh,
                position,
            ),
        }
    }

    /// Masked materials' vertices: position, `TEXCOORD_0`, `TEXCOORD_1` and `COLOR_0`.
    #[vertex]
    pub fn vs_prez_mask(
        #[location(0)] position: Vec3,
        #[location(1)] uv0: Vec2,
        #[location(2)] uv1: Vec2,
        #[location(3)] color: Vec4,
        #[builtin(instance_index)] draw: u32,
    ) -> MaskVsOut {
        MaskVsOut {
            clip: clip_position(
                CAMERA.view_projection,
                DRAWS[draw].world_from_mesh,
                position,
            ),
            uv0,
            uv1,
            color_alpha: color.w,
            material: DRAWS[draw].material,
        }
    }

    /// Masked materials: texels below the cutoff leave no depth.
    #[fragment]
    pub fn fs_prez_mask(input: MaskVsOut) {
        if alpha_mask && mask_cuts(input) {
            discard();
        }
    }
}
