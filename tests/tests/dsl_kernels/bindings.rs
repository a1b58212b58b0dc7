//! A library and a module whose bindings are numbered out of order, across two groups, with a
//! texture, a sampler and a binding only one variant has: what the generated bind-group
//! builders must number from the reflection (`dsl_gpu::bind_groups_built_by_name_*`).

/// A scale factor at group 0, binding 5, owned by the library: its part of a using module's
/// group 0 builder.
#[shader_dsl::library]
pub mod scale_lib {
    pub struct Scale {
        pub factor: f32,
        pub bias: f32,
    }

    #[uniform(group = 0, binding = 5)]
    static SCALE: Scale;

    pub fn scaled(x: f32) -> f32 {
        x * SCALE.factor + SCALE.bias
    }
}

/// `OUTPUT[i] = scaled(INPUT[i]) + texel i of row 0 of `TEXELS` (red, sampled at the texel
/// centre) + `OFFSETS[i]` where the variant has them.
#[shader_dsl::shader(
    axes(offset: bool = [false, true] => "offset"),
    uses(crate::dsl_kernels::bindings::scale_lib),
)]
pub mod bound_by_name {
    #[storage(group = 0, binding = 7)]
    static INPUT: [f32];
    #[storage(group = 0, binding = 2, read_write)]
    static OUTPUT: [f32];
    #[texture(group = 1, binding = 3)]
    static TEXELS: Texture2d<f32>;
    #[sampler(group = 1, binding = 0)]
    static NEAREST: Sampler;
    #[storage(group = 1, binding = 9)]
    #[when(offset)]
    static OFFSETS: [f32];

    #[compute(workgroup_size(64, 1, 1))]
    pub fn main(#[builtin(global_invocation_id)] gid: UVec3) {
        // One workgroup of 64 over arrays of 64.
        let i = gid.x;
        let width = TEXELS.dimensions().x;
        let uv = Vec2::new((i as f32 + 0.5) / width as f32, 0.5);
        let mut v = scaled(INPUT[i]) + TEXELS.sample_level(NEAREST, uv, 0.0).x;
        if offset {
            v += OFFSETS[i];
        }
        OUTPUT[i] = v;
    }
}
