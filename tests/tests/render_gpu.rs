//! The renderer end to end on the committed glTF scene: culling never changes the image. For
//! seeded light sets, the tiled, 2.5D and clustered Forward+ images equal the naive forward image
//! (every light at every pixel) within a stated tolerance, at MSAA 1 and 4.

use std::path::Path;

use renderer::frame::setup::{framing_camera, procedural_lights};
use renderer::frame::{RenderPath, Renderer, RendererConfig};
use renderer::readback;
use renderer::scene::Scene;
use tests::gpu::gpu_test;

fn render(path: RenderPath, msaa: u32, seed: u64) -> Vec<u8> {
    let scene_path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/AlphaBlendModeTest/AlphaBlendModeTest.glb");
    let scene = Scene::load(scene_path).unwrap_or_else(|e| panic!("{e}"));
    let (w, h) = (96, 64);
    gpu_test(|gpu| {
        let config = RendererConfig {
            width: w,
            height: h,
            msaa,
            path,
            tile: 16,
            ..Default::default()
        };
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        renderer.prepare_scene(&scene);
        let radius = (scene.bounds.max - scene.bounds.min).length();
        renderer.set_lights(&procedural_lights(
            scene.bounds,
            64,
            seed,
            radius * 0.05,
            radius * 0.3,
        ));
        let target = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("target"),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: config.output_format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let camera = framing_camera(scene.bounds, w as f32 / h as f32);
        renderer.render(&camera, &target).expect("frame");
        renderer.finish();
        let dropped = renderer.culling_counters().map_or(0, |c| c.dropped);
        assert_eq!(
            dropped, 0,
            "{path:?}: the comparison needs complete light lists"
        );
        readback::read_texture_rgba8(&gpu.device, &gpu.queue, &target).expect("readback")
    })
}

#[test]
fn culling_never_changes_the_image() {
    for msaa in [1, 4] {
        for seed in [1u64, 2] {
            let naive = render(RenderPath::Naive, msaa, seed);
            let lit = naive
                .chunks(4)
                .filter(|p| p[0] > 8 || p[1] > 8 || p[2] > 8)
                .count();
            assert!(
                lit > naive.len() / 4 / 10,
                "the scene must be visibly lit ({lit} pixels)"
            );
            for path in [
                RenderPath::Tiled,
                RenderPath::Depth25,
                RenderPath::Clustered,
            ] {
                let culled = render(path, msaa, seed);
                // Tolerance: one 8-bit step per channel. Culled paths sum the same lights in a
                // different order (f32 addition is not associative) and lights dropped as
                // borderline by a plane test contribute less than the window's last 1e-4.
                let worst = naive
                    .iter()
                    .zip(&culled)
                    .map(|(a, b)| a.abs_diff(*b))
                    .max()
                    .unwrap_or(0);
                assert!(
                    worst <= 1,
                    "{path:?} at MSAA {msaa}, seed {seed}: differs from naive by {worst}"
                );
            }
        }
    }
}

#[test]
fn heatmap_view_shows_list_counts_with_a_legend_and_refuses_the_naive_path() {
    use renderer::frame::{FrameView, RenderError};
    let scene_path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/AlphaBlendModeTest/AlphaBlendModeTest.glb");
    let scene = Scene::load(scene_path).unwrap_or_else(|e| panic!("{e}"));
    let (w, h) = (96, 64);
    gpu_test(|gpu| {
        let naive = RendererConfig {
            width: w,
            height: h,
            msaa: 1,
            path: RenderPath::Naive,
            view: FrameView::Heatmap,
            ..Default::default()
        };
        assert!(matches!(
            Renderer::new(gpu, naive),
            Err(RenderError::HeatmapNeedsLists)
        ));
        for path in [RenderPath::Tiled, RenderPath::Clustered] {
            let config = RendererConfig {
                width: w,
                height: h,
                msaa: 4,
                path,
                view: FrameView::Heatmap,
                heatmap_max: 16,
                ..Default::default()
            };
            let mut renderer = Renderer::new(gpu, config).expect("renderer");
            renderer.prepare_scene(&scene);
            let radius = (scene.bounds.max - scene.bounds.min).length();
            renderer.set_lights(&procedural_lights(
                scene.bounds,
                64,
                3,
                radius * 0.05,
                radius * 0.3,
            ));
            let target = gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("heatmap target"),
                size: wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: config.output_format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            });
            let report = renderer
                .render(&framing_camera(scene.bounds, w as f32 / h as f32), &target)
                .expect("frame");
            assert!(
                report.graph_dot.contains("light heatmap"),
                "{}",
                report.graph_dot
            );
            assert!(
                !report.graph_dot.contains("\"#3 forward\""),
                "the lit passes are not scheduled"
            );
            renderer.finish();
            let rgba =
                readback::read_texture_rgba8(&gpu.device, &gpu.queue, &target).expect("readback");
            // The legend strip (bottom rows) runs from the cold end to the hot end of the ramp.
            let px =
                |x: u32, y: u32| &rgba[((y * w + x) * 4) as usize..((y * w + x) * 4 + 3) as usize];
            let (left, right) = (px(1, h - 2), px(w - 2, h - 2));
            assert!(
                right[0] > left[0] && left[2] >= right[2],
                "{path:?}: legend runs cold to hot: {left:?} .. {right:?}"
            );
            // Pixels over lit geometry show a non-zero count.
            let coloured = (0..h - 16)
                .flat_map(|y| (0..w).map(move |x| (x, y)))
                .filter(|&(x, y)| px(x, y) != [0, 0, 0])
                .count();
            assert!(
                coloured > 100,
                "{path:?}: cells with lights are coloured ({coloured})"
            );
        }
    });
}

/// Regression: with MSAA, edge fragments are shaded at the pixel centre, which may lie in a froxel
/// no visible sample occupies; skipping empty froxels there lost lights on DamagedHelmet.
#[test]
fn clustered_equals_naive_on_a_shared_scene_with_msaa() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/scenes/DamagedHelmet/glTF-Binary/DamagedHelmet.glb");
    assert!(
        path.is_file(),
        "shared scene {} is missing: this test needs ../shared/scenes",
        path.display()
    );
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let (w, h) = (160, 90);
    let frame = |path: RenderPath| {
        gpu_test(|gpu| {
            let config = RendererConfig {
                width: w,
                height: h,
                msaa: 4,
                path,
                ..Default::default()
            };
            let mut renderer = Renderer::new(gpu, config).expect("renderer");
            renderer.prepare_scene(&scene);
            let size = (scene.bounds.max - scene.bounds.min).length();
            renderer.set_lights(&procedural_lights(
                scene.bounds,
                1024,
                1,
                size * 0.03,
                size * 0.2,
            ));
            let target = gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("target"),
                size: wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: config.output_format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            });
            renderer
                .render(&framing_camera(scene.bounds, w as f32 / h as f32), &target)
                .expect("frame");
            renderer.finish();
            assert_eq!(renderer.culling_counters().map_or(0, |c| c.dropped), 0);
            readback::read_texture_rgba8(&gpu.device, &gpu.queue, &target).expect("readback")
        })
    };
    let naive = frame(RenderPath::NaivePrez);
    let clustered = frame(RenderPath::Clustered);
    let worst = naive
        .iter()
        .zip(&clustered)
        .map(|(a, b)| a.abs_diff(*b))
        .max()
        .unwrap_or(0);
    assert!(worst <= 1, "clustered differs from naive by {worst}");
}
