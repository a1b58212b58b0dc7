#[shader_dsl::shader]
mod m {
    #[uniform(group = 0)]
    static PARAMS: UVec4;
    #[compute(workgroup_size(1))]
    fn main() {}
}
fn main() {}
