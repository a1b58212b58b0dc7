//! Targets kept between frames and never cleared. The G-buffer (`passes::deferred::gbuffer`)
//! and the visibility path's ID target (`passes::visibility::raster`): their sky samples keep
//! what the texture held, here a surface of the frame before, so every reader must test the
//! depth first. The overlay of blended surfaces (`passes::overlay_erase`): what the frame before
//! drew into it must have been erased. So a renderer's frame after one whose surfaces covered
//! the whole screen equals a new renderer's first frame (whose targets start zeroed), on TBDR
//! per-sample, the deferred path with its light volumes, and the visibility path's shading
//! kernel with either rasteriser. (`particle_render_gpu.rs` checks the particles' eraser.)

use super::*;
use tests::frames::largest_difference;

#[test]
fn sky_over_an_earlier_frames_surfaces_equals_a_first_frame() {
    gpu_test(|gpu| {
        let stage = courtyard_stage();
        // Down at the floor: surfaces on every pixel, written into every G-buffer sample.
        let floor = FrameCamera::look_at(
            glam::Vec3::new(0.0, 6.0, 0.5),
            glam::Vec3::ZERO,
            glam::Vec3::Y,
            60f32.to_radians(),
            stage.size.0 as f32 / stage.size.1 as f32,
            (0.1, 100.0),
        );
        let cases = [
            (RenderPath::TbdrPerSample, VisibilityRaster::Hardware),
            (RenderPath::Deferred, VisibilityRaster::Hardware),
            (RenderPath::Visibility, VisibilityRaster::Hardware),
            (RenderPath::Visibility, VisibilityRaster::Compute),
        ];
        for (path, visibility_raster) in cases {
            let config = (stage.look)(RendererConfig {
                width: stage.size.0,
                height: stage.size.1,
                msaa: 4,
                path,
                tile: 16,
                visibility_raster,
                ..Default::default()
            });
            let path = format!("{path:?} ({visibility_raster:?} raster)");
            let render = |renderer: &mut Renderer, camera: &FrameCamera| {
                let target = create_target(gpu.device(), &config);
                renderer.render(camera, &target).expect("frame");
                renderer.finish();
                readback::read_texture_rgba8(gpu.device(), gpu.queue(), &target).expect("readback")
            };
            let new_renderer = || {
                let mut renderer = Renderer::new(gpu, config).expect("renderer");
                renderer.prepare_scene(&stage.scene).expect("scene");
                renderer.set_lights(&stage.lights).expect("lights");
                renderer
            };
            let mut fresh = new_renderer();
            let first = render(&mut fresh, &stage.camera);
            let mut reused = new_renderer();
            let covered = render(&mut reused, &floor);
            let sky = |rgba: &[u8]| rgba.chunks(4).filter(|p| p == &&first[..4]).count();
            assert_eq!(sky(&covered), 0, "{path}: the floor view has no sky");
            assert!(
                sky(&first) > first.len() / 4 / 10,
                "{path}: the stage's view shows sky"
            );
            let after = render(&mut reused, &stage.camera);
            let worst = largest_difference(&first, &after);
            let differing = first
                .chunks(4)
                .zip(after.chunks(4))
                .filter(|(a, b)| a != b)
                .count();
            eprintln!("{path}: {differing} pixels differ, by at most {worst}");
            assert!(
                worst <= 1,
                "{path}: the frame after the floor's differs from a first frame by {worst} \
                 ({differing} pixels)"
            );
        }
    });
}
