#[shader_dsl::shader]
mod m {
    pub struct VsOut {
        #[builtin(position)]
        pub clip: Vec4,
        #[location(0)]
        #[invariant]
        pub uv: Vec2,
    }
    #[vertex]
    fn vs(#[location(0)] p: Vec4) -> VsOut {
        VsOut { clip: p, uv: p.xy() }
    }
}
fn main() {}
