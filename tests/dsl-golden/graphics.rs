// Golden: a vertex + fragment pair with IO structs, builtins, locations and interpolation,
// sampled/depth/array textures, samplers (plain and comparison), derivatives, and an MSAA axis.
#[shader_dsl::shader(axes(msaa: u32 = [1, 4]))]
pub mod graphics {
    pub struct Globals {
        pub view_proj: Mat4,
        pub light_dir: Vec3,
        pub time: f32,
    }

    pub struct VsOut {
        #[builtin(position)]
        #[invariant]
        pub clip: Vec4,
        #[location(0)]
        pub uv: Vec2,
        #[location(1)]
        #[interpolate(flat)]
        pub layer: u32,
        #[location(2)]
        #[interpolate(perspective, centroid)]
        pub normal: Vec3,
    }

    pub struct FsOut {
        #[location(0)]
        pub color: Vec4,
        #[builtin(frag_depth)]
        pub depth: f32,
    }

    #[uniform(group = 0, binding = 0)]
    static GLOBALS: Globals;
    #[texture(group = 0, binding = 1)]
    static ALBEDO: Texture2d<f32>;
    #[texture(group = 0, binding = 2)]
    static LAYERS: Texture2dArray;
    #[texture(group = 0, binding = 3)]
    static SHADOW: TextureDepth2d;
    #[sampler(group = 0, binding = 4)]
    static LINEAR: Sampler;
    #[sampler(group = 0, binding = 5)]
    static SHADOW_CMP: SamplerComparison;
    #[texture(group = 0, binding = 6)]
    static SCENE_DEPTH: TextureDepthMultisampled2d;
    #[texture(group = 1, binding = 0, unfilterable)]
    static IDS: Texture2d<u32>;

    #[vertex]
    pub fn vs(#[builtin(vertex_index)] vi: u32, #[builtin(instance_index)] ii: u32, #[location(0)] pos: Vec3) -> VsOut {
        let uv = Vec2::new((vi & 1u32) as f32, (vi >> 1u32) as f32);
        let clip = GLOBALS.view_proj * pos.extend(1.0);
        VsOut { clip, uv, layer: ii, normal: GLOBALS.light_dir }
    }

    #[fragment]
    pub fn fs(
        input: VsOut,
        #[builtin(front_facing)] front: bool,
        #[builtin(sample_index)] sample: u32,
    ) -> FsOut {
        let frag = input.clip;
        let base = ALBEDO.sample(LINEAR, input.uv);
        let layered = LAYERS.sample_level(LINEAR, input.uv, input.layer, 0.0);
        let lit = SHADOW.sample_compare(SHADOW_CMP, input.uv, 0.5);
        let lit_lod = SHADOW.sample_compare_level(SHADOW_CMP, input.uv, 0.5);
        let shadow_raw = SHADOW.sample_level(LINEAR, input.uv, 0);
        let coords = frag.xy().as_uvec2();
        let mut depth = 0.0;
        if msaa > 1 {
            depth = SCENE_DEPTH.load(coords, sample);
        } else {
            depth = SCENE_DEPTH.load(coords, 0u32);
        }
        let dims = ALBEDO.dimensions();
        let id = IDS.load(coords % dims, 0u32).x;
        let edge = dpdx(input.uv.x).abs() + dpdy(input.uv.y).abs() + fwidth(depth);
        let mut color = base * lit + layered * lit_lod + Vec4::splat(edge + shadow_raw);
        if !front {
            color = color * 0.5;
        }
        let n = input.normal.normalize().dot(GLOBALS.light_dir).max(0.0);
        FsOut {
            color: Vec4::new(color.x * n, color.y, color.z, (id as f32) + GLOBALS.time),
            depth: depth.min(frag.z) + (sample as f32) * 0.0,
        }
    }

    #[fragment]
    pub fn fs_simple(#[location(0)] uv: Vec2) -> Vec4 {
        ALBEDO.sample(LINEAR, uv) * SCENE_DEPTH.num_samples() as f32
    }
}
