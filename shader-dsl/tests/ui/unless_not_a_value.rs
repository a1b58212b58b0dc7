#[shader_dsl::shader(axes(msaa: u32 = [1, 4] => "msaa" unless 2))]
mod m {
    #[compute(workgroup_size(1))]
    fn main() {}
}
fn main() {}
