//! [`VisibilityRaster::Auto`], the default: the compute rasteriser where the device has 64-bit
//! atomic min/max and the 21 storage buffers a stage its shading kernels bind, the hardware
//! raster elsewhere. The renderer makes the choice when it is created or reconfigured, and its
//! frame then runs that raster's passes.

use renderer::frame::{RenderPath, Renderer, RendererConfig, VisibilityRaster, create_target};
use renderer::gpu::Capabilities;
use tests::gpu::gpu_test;
use tests::tbdr_stage::courtyard_stage;

#[test]
fn the_default_raster_is_the_compute_one_where_the_device_has_what_it_needs() {
    use VisibilityRaster::{Auto, Compute, Hardware};
    gpu_test(|gpu| {
        let (caps, limits) = (gpu.capabilities(), gpu.device().limits());
        assert!(
            caps.int64_atomic_min_max && limits.max_storage_buffers_per_shader_stage >= 21,
            "lavapipe has 64-bit atomic min/max and 21 storage buffers a stage: {caps:?}"
        );
        assert_eq!(Auto.for_device(caps, &limits), Compute);
        let without = Capabilities {
            int64_atomic_min_max: false,
            ..caps.clone()
        };
        assert_eq!(Auto.for_device(&without, &limits), Hardware);
        let fewer = wgpu::Limits {
            max_storage_buffers_per_shader_stage: 20,
            ..limits.clone()
        };
        assert_eq!(Auto.for_device(caps, &fewer), Hardware);
        for chosen in [Hardware, Compute] {
            assert_eq!(chosen.for_device(&without, &fewer), chosen, "asked for");
        }

        let stage = courtyard_stage();
        let config = RendererConfig {
            width: stage.size.0,
            height: stage.size.1,
            path: RenderPath::Visibility,
            ..Default::default()
        };
        assert_eq!(config.visibility_raster, Auto, "the default");
        let target = create_target(gpu.device(), &config);
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        renderer
            .prepare_scene(&stage.scene)
            .expect("the scene fits");
        renderer.set_lights(&stage.lights).expect("lights fit");
        let mut passes_of = |raster| {
            renderer
                .reconfigure(RendererConfig {
                    visibility_raster: raster,
                    ..config
                })
                .expect("the device runs both rasters");
            let chosen = renderer.config().visibility_raster;
            renderer.render(&stage.camera, &target).expect("frame");
            renderer.finish();
            (chosen, renderer.graph_passes().expect("a frame's graph"))
        };
        for (asked, runs) in [(Auto, Compute), (Hardware, Hardware), (Auto, Compute)] {
            let (chosen, passes) = passes_of(asked);
            assert_eq!(chosen, runs, "{asked:?}");
            let computes = passes.iter().any(|p| p == "compute raster");
            assert_eq!(computes, runs == Compute, "{asked:?}: {passes:?}");
        }
    });
}
