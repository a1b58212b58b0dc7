// Golden: a small compute kernel with one axis, a helper with `&mut`, loops and atomics.
#[shader_dsl::shader(axes(tile: u32 = [8, 16] => "t"))]
pub mod compute_basic {
    pub struct Params {
        pub scale: f32,
        pub count: u32,
    }

    const MAX_ITEMS: u32 = 64;

    #[uniform(group = 0, binding = 0)]
    static PARAMS: Params;
    #[storage(group = 0, binding = 1, read_write)]
    static DATA: [f32];
    #[workgroup]
    static SHARED: [f32; tile * tile];
    #[workgroup]
    static COUNTER: Atomic<u32>;

    fn accumulate(x: f32, acc: &mut f32) {
        *acc += x * PARAMS.scale;
    }

    #[compute(workgroup_size(tile, tile, 1))]
    pub fn main(#[builtin(global_invocation_id)] gid: UVec3, #[builtin(local_invocation_index)] lid: u32) {
        let i = gid.x;
        if i >= PARAMS.count {
            return;
        }
        let mut acc = 0.0;
        for k in 0..MAX_ITEMS {
            accumulate(DATA[i] + k as f32, &mut acc);
        }
        SHARED[lid] = acc;
        workgroup_barrier();
        if tile == 16 {
            COUNTER.fetch_add(1u32);
        }
        DATA[i] = SHARED[lid].max(0.0);
    }
}
