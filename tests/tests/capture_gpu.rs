//! Frame capture (`Renderer::capture_next_frame` / `take_capture`), which the benchmark's cull
//! efficiency rests on: the probed depth lands where the kernel says, and every light that
//! reaches a probed surface sample is counted in that sample's cell list (culling is
//! conservative), so the efficiency is at least 1.

use renderer::culling::reference::exact::Efficiency;
use renderer::demo::procedural_lights;
use renderer::frame::ConfigError;
use renderer::frame::{RenderError, RenderPath, Renderer, RendererConfig, VisibilityRaster};
use renderer::frame::{create_target, framing_camera};
use tests::frames::committed_scene;
use tests::gpu::gpu_test;

fn capture(path: RenderPath, msaa: u32, stride: u32) -> renderer::frame::capture::FrameCapture {
    capture_with(path, msaa, stride, VisibilityRaster::Hardware, None)
}

/// A capture of a 96 × 64 frame; where `first` is a size, of a frame after a captured frame
/// of that size and a resize (so what a pass keeps between frames is used again, or not).
fn capture_with(
    path: RenderPath,
    msaa: u32,
    stride: u32,
    raster: VisibilityRaster,
    first: Option<(u32, u32)>,
) -> renderer::frame::capture::FrameCapture {
    let scene = committed_scene();
    let (width, height) = first.unwrap_or((96, 64));
    let config = RendererConfig {
        width,
        height,
        msaa,
        path,
        tile: 16,
        visibility_raster: raster,
        ..Default::default()
    };
    let size = (scene.bounds.max - scene.bounds.min).length();
    let lights = procedural_lights(scene.bounds, 128, 5, size * 0.05, size * 0.2);
    gpu_test(|gpu| {
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        renderer
            .prepare_scene(&scene)
            .expect("the scene fits the device");
        renderer.set_lights(&lights).expect("lights fit");
        let camera = framing_camera(scene.bounds, 1.5);
        if first.is_some() {
            renderer.capture_next_frame(stride).expect("capture");
            let target = create_target(gpu.device(), &config);
            renderer.render(&camera, &target).expect("frame");
            renderer
                .take_capture()
                .expect("readback")
                .expect("a capture");
            renderer.resize(96, 64).expect("resize");
        }
        let config = RendererConfig {
            width: 96,
            height: 64,
            ..config
        };
        let target = create_target(gpu.device(), &config);
        assert!(
            renderer.take_capture().expect("take").is_none(),
            "nothing asked yet"
        );
        renderer.capture_next_frame(stride).expect("capture");
        renderer.render(&camera, &target).expect("frame");
        let capture = renderer
            .take_capture()
            .expect("readback")
            .expect("a capture");
        assert!(
            renderer.take_capture().expect("take").is_none(),
            "a capture is taken once"
        );
        capture
    })
}

#[test]
fn every_reaching_light_is_listed_for_its_sample() {
    for (path, msaa) in [
        (RenderPath::Tiled, 1),
        (RenderPath::Depth25, 4),
        (RenderPath::Clustered, 4),
    ] {
        let c = capture(path, msaa, 1);
        assert_eq!(c.grid.x * c.grid.y, 96 * 64, "stride 1 probes every pixel");
        let surface = c.surface_probes();
        let sky = c.probes.iter().filter(|&&d| d >= 1.0).count();
        assert!(
            surface.len() > 500 && sky > 500,
            "{path:?}: the framed scene has both surface ({}) and sky ({sky})",
            surface.len()
        );
        let method = c.method.expect("a culled path has a method");
        let counts = c.cell_counts.as_ref().expect("the grid was copied");
        let view: Vec<_> = c.lights.iter().map(|l| l.to_view(c.camera.view)).collect();
        for p in &surface {
            // Clearly inside (0.1% margin): borderline lights may go either way on a GPU.
            let reaching = view
                .iter()
                .filter(|l| l.center.distance(p.position) < l.radius * 0.999)
                .count() as u32;
            let cell = method.cell_of(96, 64, p.x, p.y, -p.position.z);
            assert!(
                counts[cell] >= reaching,
                "{path:?} MSAA {msaa}: pixel ({}, {}) is reached by {reaching} lights but its \
                 cell lists {}",
                p.x,
                p.y,
                counts[cell]
            );
        }
        let reaching = c.lights_reaching(&surface);
        let e: Efficiency = c.cull_efficiency(&surface, &reaching).expect("culled path");
        assert!(e.reaching > 0, "{path:?}: some lights reach the surface");
        assert!(
            e.ratio() >= 1.0,
            "{path:?}: lists are a superset, got {}",
            e.ratio()
        );
    }
}

#[test]
fn strided_probes_follow_the_kernels_pattern() {
    let full = capture(RenderPath::NaivePrez, 4, 1);
    let strided = capture(RenderPath::NaivePrez, 4, 5);
    assert!(
        full.method.is_none() && full.cell_counts.is_none(),
        "no lists without culling"
    );
    assert_eq!((strided.grid.x, strided.grid.y), (20, 13));
    for j in 0..strided.grid.y {
        for i in 0..strided.grid.x {
            let (x, y, s) = strided.probe_sample(i, j);
            let (fx, fy, fs) = full.probe_sample(x, y);
            assert_eq!((fx, fy), (x, y));
            let got = strided.probes[(j * strided.grid.x + i) as usize];
            let want = full.probes[(y * full.grid.x + x) as usize];
            // The full capture reads sample (x + y) % 4 of the same pixel; equal when that is
            // the same sample, and both are real depths (or sky) of the same frame either way.
            if fs == s {
                assert_eq!(got.to_bits(), want.to_bits(), "probe ({i}, {j})");
            }
            assert!(
                (0.0..=1.0).contains(&got),
                "probe ({i}, {j}) holds depth {got}"
            );
        }
    }
}

#[test]
fn capture_needs_the_depth_prepass() {
    gpu_test(|gpu| {
        let config = RendererConfig {
            path: RenderPath::Naive,
            msaa: 1,
            ..Default::default()
        };
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        let err = renderer.capture_next_frame(4).unwrap_err();
        assert!(matches!(
            err,
            RenderError::Config(ConfigError::CaptureNeedsDepth)
        ));
        assert!(err.to_string().contains("naive-prez"), "{err}");
    });
}

/// On the compute rasteriser's frame no pass of the renderer reads a depth target, so the
/// graph culls the pass that resolves one from the rasteriser's samples; a capture's depth
/// probe reads one, and gets it: the same depths as the hardware raster's frame, the masked
/// quads of the committed scene included (the resolve runs after they merge into the samples).
#[test]
fn a_capture_of_the_compute_rasterisers_frame_probes_its_resolved_depth() {
    // After a frame of another size, so the depth resolve's kept bind group is built again.
    let probes = |raster| capture_with(RenderPath::Visibility, 4, 1, raster, Some((80, 48))).probes;
    let (hardware, compute) = (
        probes(VisibilityRaster::Hardware),
        probes(VisibilityRaster::Compute),
    );
    assert_eq!(hardware.len(), compute.len());
    let surfaces = hardware.iter().filter(|&&d| d < 1.0).count();
    let differ = (hardware.iter().zip(&compute))
        .filter(|(a, b)| (*a - *b).abs() > 1e-4)
        .count();
    eprintln!(
        "{differ} of {} probes differ ({surfaces} on a surface)",
        hardware.len()
    );
    // Measured: 1,111 of 6,144 on a surface, none differing.
    assert!(
        surfaces * 8 > hardware.len(),
        "{surfaces} probes on a surface"
    );
    // Edges: the compute rasteriser evaluates them in float where the hardware snaps
    // vertices to its sub-pixel grid.
    assert!(
        differ * 100 <= hardware.len(),
        "{differ} of {} probed depths differ from the hardware raster's",
        hardware.len()
    );
}
