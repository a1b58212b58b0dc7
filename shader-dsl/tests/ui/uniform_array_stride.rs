#[shader_dsl::shader]
mod m {
    pub struct Params {
        pub count: u32,
        pub weights: [f32; 8],
    }
    #[uniform(group = 0, binding = 0)]
    static PARAMS: Params;
    #[compute(workgroup_size(1))]
    fn main() {
        let w = PARAMS.weights[0];
    }
}
fn main() {}
