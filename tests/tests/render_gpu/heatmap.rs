//! The heatmap view: list counts per tile with a legend, refused on the naive path.

use super::*;

#[test]
fn heatmap_view_shows_list_counts_with_a_legend_and_refuses_the_naive_path() {
    use renderer::frame::{FrameView, RenderError};
    let scene = committed_scene();
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
            Err(RenderError::Config(ConfigError::HeatmapNeedsLists))
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
            let frame = render_frame(gpu, &scene, config, &lights(&scene, 64, 3, 0.05, 0.3));
            let dot = &frame.graph_dot;
            assert!(dot.contains("light heatmap"), "{dot}");
            assert!(
                !dot.contains("\"#3 forward\""),
                "the lit passes are not scheduled"
            );
            let rgba = &frame.rgba;
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
