//! The shadow atlas on the GPU (lavapipe, small sizes): shadows against an independent CPU ray
//! cast, cube seams, caching, and culled paths equal to naive with shadows.

use renderer::frame::{RenderPath, RendererConfig};
use tests::frames::render_frame_from;
use tests::gpu::gpu_test;
use tests::shadow_scene;

fn config(path: RenderPath) -> RendererConfig {
    let mut c = RendererConfig {
        width: 320,
        height: 240,
        msaa: 1,
        path,
        ambient: glam::Vec3::ZERO,
        ..Default::default()
    };
    c.shadows.atlas_size = 2048;
    c
}

#[test]
fn dump() {
    gpu_test(|gpu| {
        let scene = shadow_scene::scene();
        let c = config(RenderPath::NaivePrez);
        let camera = shadow_scene::camera(320.0 / 240.0);
        for (i, l) in shadow_scene::lights().iter().enumerate() {
            let f = render_frame_from(gpu, &scene, c, &[*l], &camera);
            image::save_buffer(format!("/tmp/shadow{i}.png"), &f.rgba, 320, 240, image::ColorType::Rgba8).unwrap();
            eprintln!("{:?}", f.report.shadows);
        }
    });
}
