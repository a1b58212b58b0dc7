#[shader_dsl::shader]
mod m {
    #[compute(workgroup_size(1))]
    fn main(#[builtin(global_invocation_id)] gid: u32) {}
}
fn main() {}
