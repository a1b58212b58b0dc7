// A generated bind-group builder is typed by each binding's kind: a texture view where the
// module binds a sampler does not compile.
#[shader_dsl::shader]
mod m {
    #[texture(group = 0, binding = 0)]
    static COLOUR: Texture2d<f32>;
    #[sampler(group = 0, binding = 1)]
    static LINEAR: Sampler;
    #[storage(group = 0, binding = 2, read_write)]
    static OUT: [Vec4];
    #[compute(workgroup_size(1))]
    fn main() {
        OUT[0] = COLOUR.sample_level(LINEAR, Vec2::new(0.5, 0.5), 0.0);
    }
}

fn bind<'a>(view: &'a wgpu::TextureView, out: &'a wgpu::Buffer) -> m::Group0<'a> {
    m::Group0 {
        colour: view,
        linear: view,
        out: out.as_entire_buffer_binding(),
    }
}

fn main() {
    let _ = bind;
}
