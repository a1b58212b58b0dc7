//! The pass contract: a pass written outside the renderer (here, in this test) joins the frame
//! through `Renderer::insert_pass_after`, without any change to `renderer::frame`. The graph
//! schedules it, it reads what an earlier pass produced (`FrameResources::hdr`), its GPU work
//! lands in the frame's submission, and its result is what the frame really held.

use renderer::frame::ConfigError;
use std::path::Path;

use renderer::demo::procedural_lights;
use renderer::frame::{RenderError, RenderPath, Renderer, RendererConfig};
use renderer::frame::{create_target, framing_camera};
use renderer::frame_data::{FrameInputs, FrameResources, HDR_FORMAT};
use renderer::graph::{BufferAccess, ImportAccess, RenderGraph, TextureAccess};
use renderer::passes::Pass;
use renderer::readback;
use renderer::scene::Scene;
use tests::gpu::gpu_test;

const WIDTH: u32 = 96;
const HEIGHT: u32 = 64;
/// Bytes per Rgba16Float texel.
const TEXEL: u32 = 8;

/// A debug pass that copies the resolved HDR colour into a buffer the test reads back.
#[derive(Debug)]
struct HdrSnapshot {
    buffer: wgpu::Buffer,
}

impl Pass for HdrSnapshot {
    fn name(&self) -> &'static str {
        "hdr snapshot"
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        _frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let hdr = resources
            .hdr
            .ok_or(RenderError::Config(ConfigError::MissingInput {
                pass: "hdr snapshot",
                input: "HDR colour",
            }))?;
        let mut out =
            resources.import_buffer(graph, "hdr snapshot", &self.buffer, ImportAccess::ReadWrite);
        let target = out;
        graph
            .add_pass(self.name())
            .read_texture(hdr, TextureAccess::CopySrc)
            .write_buffer(&mut out, BufferAccess::CopyDst)
            .execute(move |ctx| {
                let texture = ctx.texture(hdr).clone();
                let buffer = ctx.buffer(target).clone();
                ctx.encoder.copy_texture_to_buffer(
                    texture.as_image_copy(),
                    wgpu::TexelCopyBufferInfo {
                        buffer: &buffer,
                        layout: wgpu::TexelCopyBufferLayout {
                            offset: 0,
                            bytes_per_row: Some(WIDTH * TEXEL),
                            rows_per_image: Some(HEIGHT),
                        },
                    },
                    texture.size(),
                );
            });
        Ok(())
    }
}

#[test]
fn a_pass_from_outside_the_renderer_joins_the_frame() {
    let scene = Scene::load(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes/AlphaBlendModeTest/AlphaBlendModeTest.glb"),
    )
    .expect("committed scene");
    let config = RendererConfig {
        width: WIDTH,
        height: HEIGHT,
        msaa: 4,
        path: RenderPath::Tiled,
        ..Default::default()
    };
    assert_eq!(HDR_FORMAT, wgpu::TextureFormat::Rgba16Float);
    gpu_test(|gpu| {
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        let buffer = gpu.device().create_buffer(&wgpu::BufferDescriptor {
            label: Some("hdr snapshot"),
            size: u64::from(WIDTH * HEIGHT * TEXEL),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let err = renderer
            .insert_pass_after(
                "no such pass",
                Box::new(HdrSnapshot {
                    buffer: buffer.clone(),
                }),
            )
            .unwrap_err();
        assert!(
            matches!(err, RenderError::Config(ConfigError::NoSuchPass(_))),
            "{err}"
        );
        renderer
            .insert_pass_after(
                "forward",
                Box::new(HdrSnapshot {
                    buffer: buffer.clone(),
                }),
            )
            .expect("insert");
        assert_eq!(
            renderer.pass_names(),
            [
                "scene culling",
                "pre-z",
                "occlusion culling",
                "pre-z (late)",
                "light culling",
                "shadow atlas",
                "particle simulation",
                "particle lighting",
                "forward",
                "hdr snapshot",
                "particles",
                "tonemap",
                "depth probe"
            ]
        );
        assert!(renderer.pass::<HdrSnapshot>().is_some());

        renderer
            .prepare_scene(&scene)
            .expect("the scene fits the device");
        renderer
            .set_lights(&procedural_lights(scene.bounds, 32, 3, 0.5, 2.0))
            .expect("lights fit");
        let target = create_target(gpu.device(), &config);
        let camera = framing_camera(scene.bounds, WIDTH as f32 / HEIGHT as f32);
        let report = renderer.render(&camera, &target).expect("frame");
        renderer.finish();
        let dot = renderer.graph_dot().expect("a compiled graph");
        assert!(
            dot.contains("hdr snapshot"),
            "the compiled graph schedules the pass:\n{dot}"
        );

        // The snapshot is the frame's HDR image: wherever the output shows light the HDR holds
        // some, and wherever the HDR holds more than a 1/20 the output shows it (tonemapping
        // maps tiny values to 0).
        let ldr = readback::read_texture_rgba8(gpu.device(), gpu.queue(), &target).expect("ldr");
        let hdr =
            readback::read_buffer::<[u16; 4]>(gpu.device(), gpu.queue(), &buffer).expect("hdr");
        let mut lit = 0;
        for (i, (texel, pixel)) in hdr.iter().zip(ldr.chunks(4)).enumerate() {
            let brightest = texel[..3]
                .iter()
                .map(|&h| half::f16::from_bits(h).to_f32())
                .fold(0.0, f32::max);
            let shown = pixel[..3].iter().any(|&b| b > 0);
            assert!(
                (!shown || brightest > 0.0) && (brightest <= 0.05 || shown),
                "pixel {i}: HDR {brightest}, output {pixel:?}"
            );
            lit += usize::from(brightest > 0.05);
        }
        assert!(lit > hdr.len() / 20, "the frame must be lit ({lit} pixels)");

        // The graph is compiled once: the next frame of the same shape reuses its plan (and
        // draws the same), a frame of another size compiles again.
        assert!(report.graph_compiled, "the first frame compiles its graph");
        let again = renderer.render(&camera, &target).expect("frame");
        renderer.finish();
        assert!(!again.graph_compiled, "the same graph reuses the plan");
        let ldr_again =
            readback::read_texture_rgba8(gpu.device(), gpu.queue(), &target).expect("ldr");
        assert_eq!(ldr_again, ldr, "a reused plan draws the same frame");
        renderer
            .resize(WIDTH / 2, HEIGHT)
            .expect("a size the device takes");
        let half = RendererConfig {
            width: WIDTH / 2,
            ..config
        };
        let smaller = create_target(gpu.device(), &half);
        let resized = renderer.render(&camera, &smaller).expect("frame");
        renderer.finish();
        assert!(resized.graph_compiled, "a new size compiles again");
    });
}

/// A pass whose bind group the builder refuses while `fail` is set (as a generated builder
/// refuses a resource that does not fit).
#[derive(Debug)]
struct RefusedBinding {
    fail: std::sync::Arc<std::sync::atomic::AtomicBool>,
}

impl Pass for RefusedBinding {
    fn name(&self) -> &'static str {
        "refused binding"
    }

    fn add_to_graph(
        &self,
        graph: &mut RenderGraph,
        _frame: &FrameInputs,
        _resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        let fail = self.fail.load(std::sync::atomic::Ordering::Relaxed);
        graph
            .add_pass(self.name())
            .side_effects()
            .execute(move |ctx| {
                let built = if fail {
                    Err(shader_bind::BindError::Missing {
                        variant: "refused binding".into(),
                        group: 0,
                        binding: "missing",
                        index: 0,
                    })
                } else {
                    Ok(())
                };
                let _ = ctx.bind(built);
            });
        Ok(())
    }
}

/// A frame whose pass cannot bind fails with `GraphError::Bind` and is never submitted; its
/// passes' timer queries must not reach a later frame's timings, which list the same passes
/// as a frame before the failure.
#[test]
fn a_frame_that_cannot_bind_leaves_no_timings_to_the_next() {
    use renderer::graph::GraphError;
    use std::sync::atomic::{AtomicBool, Ordering};
    let config = RendererConfig {
        width: WIDTH,
        height: HEIGHT,
        msaa: 1,
        path: RenderPath::Clustered,
        ..Default::default()
    };
    gpu_test(|gpu| {
        let scene = renderer::scene::procedural::courtyard();
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        let fail = std::sync::Arc::new(AtomicBool::new(false));
        renderer
            .insert_pass_after(
                "light culling",
                Box::new(RefusedBinding {
                    fail: std::sync::Arc::clone(&fail),
                }),
            )
            .expect("insert");
        renderer.prepare_scene(&scene).expect("scene");
        renderer
            .set_lights(&procedural_lights(scene.bounds, 32, 3, 0.5, 2.0))
            .expect("lights");
        let target = create_target(gpu.device(), &config);
        let camera = framing_camera(scene.bounds, WIDTH as f32 / HEIGHT as f32);
        let labels = |timings: &[renderer::graph::PassTiming]| -> Vec<String> {
            timings.iter().map(|t| t.pass.clone()).collect()
        };

        // Every frame's timings come back once: in a later report, or drained.
        let timed = |renderer: &mut Renderer, frames: usize| {
            let mut timings = Vec::new();
            for _ in 0..frames {
                let report = renderer.render(&camera, &target).expect("frame");
                timings.extend(report.timings);
            }
            gpu.wait_idle().expect("the frames finish");
            timings.extend(renderer.drain_timings());
            timings
        };
        let before = timed(&mut renderer, 1);
        let reference = labels(before.last().expect("the first frame's timings"));
        assert!(reference.iter().any(|p| p == "refused binding"));

        fail.store(true, Ordering::Relaxed);
        match renderer.render(&camera, &target) {
            Err(RenderError::Config(ConfigError::Graph(GraphError::Bind { pass, .. }))) => {
                assert_eq!(pass, "refused binding");
            }
            other => panic!("the frame must fail to bind, got {other:?}"),
        }
        fail.store(false, Ordering::Relaxed);
        let after = timed(&mut renderer, 2);
        assert!(!after.is_empty(), "the frames after the failure are timed");
        for timings in &after {
            assert_eq!(
                labels(timings),
                reference,
                "a frame after the failure lists other passes"
            );
            for t in timings {
                assert!(
                    t.gpu_ms.is_finite() && (0.0..1e4).contains(&t.gpu_ms),
                    "{}: {} ms",
                    t.pass,
                    t.gpu_ms
                );
            }
        }
    });
}

/// An engine pass that takes the blended overlay (`FrameResources::hdr_overlay`) before the
/// overlay pass, which then has nothing to lay over or erase.
#[derive(Debug)]
struct TakesOverlay;

impl Pass for TakesOverlay {
    fn name(&self) -> &'static str {
        "takes overlay"
    }

    fn add_to_graph(
        &self,
        _graph: &mut RenderGraph,
        _frame: &FrameInputs,
        resources: &mut FrameResources,
    ) -> Result<(), RenderError> {
        resources.hdr_overlay = None;
        Ok(())
    }
}

/// The overlay is kept between frames and erased by what drew into it, not cleared
/// (`passes::overlay_erase`). A pass that takes it before the overlay pass runs the erasers
/// leaves what was drawn in it for every later frame: the frame is refused with an error that
/// names the erasers, not drawn wrong.
#[test]
fn taking_the_overlay_before_its_erasers_run_is_an_error() {
    let config = RendererConfig {
        width: WIDTH,
        height: HEIGHT,
        msaa: 4,
        path: RenderPath::TbdrPerSample,
        ..Default::default()
    };
    gpu_test(|gpu| {
        let scene = renderer::scene::procedural::courtyard();
        let glass =
            (scene.materials.iter()).any(|m| m.alpha_mode == renderer::scene::AlphaMode::Blend);
        assert!(glass, "the courtyard has glass");
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        renderer
            .insert_pass_after("forward", Box::new(TakesOverlay))
            .expect("insert");
        renderer.prepare_scene(&scene).expect("scene");
        let target = create_target(gpu.device(), &config);
        let camera = framing_camera(scene.bounds, WIDTH as f32 / HEIGHT as f32);
        match renderer.render(&camera, &target) {
            Err(RenderError::Config(ConfigError::MissingInput { pass, input })) => {
                assert_eq!(pass, "overlay erase", "{input}");
            }
            other => panic!("the frame must be refused, got {other:?}"),
        }
    });
}
