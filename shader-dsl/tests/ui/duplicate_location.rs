#[shader_dsl::shader]
mod m {
    pub struct VsOut {
        #[builtin(position)]
        pub pos: Vec4,
        #[location(0)]
        pub uv: Vec2,
        #[location(0)]
        pub color: Vec4,
    }
    #[vertex]
    fn vs(#[builtin(vertex_index)] vi: u32) -> VsOut {
        VsOut { pos: Vec4::ZERO, uv: Vec2::ZERO, color: Vec4::ONE }
    }
}
fn main() {}
