// Golden: sampling with explicit gradients (`sample_grad`, WGSL `textureSampleGrad`) of a 2D
// texture and a 2D array texture: in a fragment loop whose trip count is non-uniform (a flat
// input), where WGSL would refuse the implicit-derivative `sample`, and in a compute entry point,
// which has no implicit derivatives at all.
#[shader_dsl::shader]
pub mod sample_grad {
    pub struct VsOut {
        #[builtin(position)]
        pub clip: Vec4,
        #[location(0)]
        pub uv: Vec2,
        #[location(1)]
        #[interpolate(flat)]
        pub taps: u32,
        #[location(2)]
        #[interpolate(flat)]
        pub layer: u32,
    }

    #[texture(group = 0, binding = 0)]
    static ALBEDO: Texture2d<f32>;
    #[texture(group = 0, binding = 1)]
    static LAYERS: Texture2dArray<f32>;
    #[sampler(group = 0, binding = 2)]
    static LINEAR: Sampler;
    #[storage(group = 0, binding = 3, read_write)]
    static OUT: [Vec4];

    #[vertex]
    pub fn vs(#[builtin(vertex_index)] vi: u32, #[builtin(instance_index)] ii: u32) -> VsOut {
        let uv = Vec2::new((vi & 1u32) as f32, (vi >> 1u32) as f32);
        let clip = Vec4::new(uv.x * 2.0 - 1.0, uv.y * 2.0 - 1.0, 0.0, 1.0);
        VsOut { clip, uv, taps: vi % 5u32, layer: ii }
    }

    #[fragment]
    pub fn fs(input: VsOut) -> Vec4 {
        // The derivatives are taken once, in uniform control flow; the loop below is not.
        let ddx = dpdx(input.uv);
        let ddy = dpdy(input.uv);
        let mut sum = Vec4::ZERO;
        for i in 0..input.taps {
            let offset = Vec2::new(i as f32 * 0.01, 0.0);
            sum += ALBEDO.sample_grad(LINEAR, input.uv + offset, ddx, ddy);
            sum += LAYERS.sample_grad(LINEAR, input.uv - offset, input.layer, ddx * 2.0, ddy * 2.0);
        }
        sum / (input.taps.max(1u32) as f32)
    }

    #[compute(workgroup_size(8))]
    pub fn cs(#[builtin(global_invocation_id)] gid: UVec3) {
        let uv = Vec2::new(gid.x as f32 / 64.0, 0.5);
        let ddx = Vec2::new(1.0 / 64.0, 0.0);
        let single = ALBEDO.sample_grad(LINEAR, uv, ddx, Vec2::ZERO);
        let layered = LAYERS.sample_grad(LINEAR, uv, gid.y, ddx, Vec2::ZERO);
        OUT[gid.x] = single + layered;
    }
}
