//! The engine example end to end, headless on whatever adapter the machine has (lavapipe in
//! CI): the engine opens its own device with the limits the renderer asks, builds a scene in
//! code (no glTF), inserts its census pass after light culling, and renders.
//!
//! Checked: the census the engine's pass took of the renderer's clustered lists equals the
//! renderer's own culling counters (entries, longest list), every listed index names a real
//! light, and the frame with the engine's pass is the frame without it, lit. The engine's own
//! material (`engine_shaders::bricks`, registered with the renderer) shows in the frame, and
//! every path draws it as naive forward does. Two views in one frame (the street camera and a
//! minimap from above, smaller, on another path) share the shadow atlas; the main view is the
//! frame a renderer without the minimap draws.

use engine_app::{Census, LightCensusPass, light_census};
use glam::{Mat4, Vec3};
use renderer::frame::{RenderPath, Renderer, RendererConfig};
use renderer::frame::{create_target, framing_camera};
use renderer::materials::MaterialProgram;
use renderer::scene::procedural::SceneBuilder;
use renderer::scene::{CustomShading, LightKind, Scene, SceneLight};
use renderer::{GpuContext, GpuOptions, readback};

const WIDTH: u32 = 128;
const HEIGHT: u32 = 96;

/// The engine's device: its own instance, adapter and device, opened with what the renderer
/// asks of the adapter (`requirements::for_adapter`).
fn engine_device() -> GpuContext {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = GpuOptions::from_env().backends;
    let instance = wgpu::Instance::new(desc);
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        ..Default::default()
    }))
    .expect("an adapter (lavapipe where there is no GPU)");
    let (features, limits) =
        renderer::gpu::requirements::for_adapter(&adapter).expect("the adapter suits the renderer");
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("engine device"),
        required_features: features,
        required_limits: limits,
        ..Default::default()
    }))
    .expect("the engine's device");
    GpuContext::from_parts(instance, adapter, device, queue).expect("the device has the limits")
}

/// A yard of boxes and spheres, built in code.
fn yard() -> Scene {
    let mut b = SceneBuilder::new();
    let ground = b.material("ground", Vec3::new(0.5, 0.5, 0.45), 0.8);
    let brick = b.material("brick", Vec3::new(0.6, 0.25, 0.2), 0.6);
    let metal = b.material("metal", Vec3::new(0.8, 0.8, 0.85), 0.3);
    b.cuboid(
        Vec3::new(-6.0, -0.2, -6.0),
        Vec3::new(6.0, 0.0, 6.0),
        ground,
    );
    for i in 0..5 {
        let x = -4.0 + 2.0 * i as f32;
        b.cuboid(
            Vec3::new(x - 0.4, 0.0, -2.0),
            Vec3::new(x + 0.4, 1.5, -1.2),
            brick,
        );
        b.sphere(Vec3::new(x, 0.6, 1.5), 0.6, metal);
    }
    let sphere = b.mesh(
        "moon",
        renderer::scene::procedural::sphere_primitive(Vec3::ZERO, 1.0, metal),
    );
    b.place(sphere, Mat4::from_translation(Vec3::new(0.0, 3.0, -4.0)));
    b.build()
}

/// A ring of coloured point lights over the yard.
fn lights() -> Vec<SceneLight> {
    (0..24)
        .map(|i| {
            let a = i as f32 / 24.0 * std::f32::consts::TAU;
            SceneLight {
                kind: LightKind::Point,
                position: Vec3::new(4.0 * a.cos(), 0.8 + (i % 3) as f32 * 0.5, 4.0 * a.sin()),
                direction: Vec3::NEG_Y,
                color: Vec3::new(0.5 + 0.5 * a.cos(), 0.6, 0.5 + 0.5 * a.sin()),
                intensity: 6.0,
                range: Some(3.0),
                casts_shadow: i % 8 == 0,
            }
        })
        .collect()
}

/// One frame of `renderer`, read back as RGBA8.
fn frame(gpu: &GpuContext, renderer: &mut Renderer, scene: &Scene) -> Vec<u8> {
    let camera = framing_camera(scene.bounds, WIDTH as f32 / HEIGHT as f32);
    let target = create_target(gpu.device(), renderer.config());
    renderer.render(&camera, &target).expect("a frame");
    renderer.finish();
    readback::read_texture_rgba8(gpu.device(), gpu.queue(), &target).expect("readback")
}

#[test]
fn an_engines_own_pass_reads_the_renderers_light_lists_through_the_generated_builders() {
    let gpu = engine_device();
    let scene = yard();
    let config = RendererConfig {
        width: WIDTH,
        height: HEIGHT,
        path: RenderPath::Clustered,
        ..Default::default()
    };
    let new_renderer = || {
        let mut r = Renderer::new(&gpu, config).expect("the renderer");
        r.prepare_scene(&scene).expect("the scene fits");
        r.set_lights(&lights()).expect("the lights fit");
        r
    };

    let mut plain = new_renderer();
    let without = frame(&gpu, &mut plain, &scene);

    let mut renderer = new_renderer();
    let census = LightCensusPass::new(&gpu, light_census::List::List2).expect("the census pass");
    renderer
        .insert_pass_after("light culling", Box::new(census))
        .expect("light culling runs on the clustered path");
    let with = frame(&gpu, &mut renderer, &scene);
    let counters = renderer.culling_counters().expect("the culling counters");
    let got: Census = renderer
        .pass::<LightCensusPass>()
        .expect("the inserted pass")
        .read(&gpu)
        .expect("the census");

    assert_eq!(counters.dropped, 0);
    assert!(
        got.entries > 24,
        "the lights are listed in many cells: {got:?}"
    );
    assert_eq!(
        got.entries, counters.requested_entries,
        "{got:?} {counters:?}"
    );
    assert_eq!(got.longest, counters.max_cell_items, "{got:?} {counters:?}");
    assert_eq!(
        got.lit_entries, got.entries,
        "an index names no light: {got:?}"
    );

    assert_eq!(with, without, "the engine's pass changed the frame");
    let lit = with
        .chunks(4)
        .filter(|p| p[0] > 24 || p[1] > 24 || p[2] > 24)
        .count();
    assert!(lit > with.len() / 4 / 10, "the yard is lit: {lit} pixels");
}

/// The yard with its brick drawn by the engine's `bricks` material.
fn bricked_yard() -> Scene {
    let mut scene = yard();
    let params = engine_shaders::bricks::Bricks::new(
        glam::Vec4::new(0.62, 0.22, 0.15, 1.0),
        glam::Vec4::new(0.8, 0.78, 0.74, 1.0),
        glam::Vec2::new(0.4, 0.25),
        0.05,
        0.0,
    );
    let brick = scene.materials.iter_mut().find(|m| m.name == "brick");
    brick.expect("the yard has brick").custom = Some(CustomShading::new("bricks", &params));
    scene
}

/// Mean and 99th percentile of the per-channel differences (RGB) of two RGBA8 frames.
fn differences(a: &[u8], b: &[u8]) -> (f64, u8) {
    let mut d: Vec<u8> = a
        .chunks(4)
        .zip(b.chunks(4))
        .flat_map(|(p, q)| (0..3).map(move |c| p[c].abs_diff(q[c])))
        .collect();
    let mean = d.iter().map(|&v| f64::from(v)).sum::<f64>() / d.len() as f64;
    d.sort_unstable();
    (mean, d[d.len() * 99 / 100])
}

#[test]
fn the_engines_own_material_shows_and_every_path_draws_it_as_naive_does() {
    let gpu = engine_device();
    let program = MaterialProgram::new(&engine_shaders::bricks::MODULE).expect("a material");
    let render = |scene: &Scene, path| {
        let config = RendererConfig {
            width: WIDTH,
            height: HEIGHT,
            path,
            msaa: 4,
            ..Default::default()
        };
        let mut r = Renderer::new(&gpu, config).expect("the renderer");
        r.register_material(program)
            .expect("the engine's material registers");
        r.prepare_scene(scene).expect("the scene fits");
        r.set_lights(&lights()).expect("the lights fit");
        frame(&gpu, &mut r, scene)
    };
    let scene = bricked_yard();
    let naive = render(&scene, RenderPath::Naive);
    let plain = render(&yard(), RenderPath::Naive);
    let changed = naive
        .chunks(4)
        .zip(plain.chunks(4))
        .filter(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > 16))
        .count();
    assert!(
        changed > 100,
        "the bricks show where glTF's brick was: {changed} pixels changed"
    );
    for path in [RenderPath::Tiled, RenderPath::Clustered] {
        let (mean, p99) = differences(&naive, &render(&scene, path));
        assert!(
            mean < 0.05 && p99 <= 1,
            "{path:?}: mean {mean:.3}, p99 {p99}"
        );
    }
    let prez = render(&scene, RenderPath::NaivePrez);
    // The deferred paths, and the visibility buffer: the engine's kernel, then glTF PBR's.
    for path in [
        RenderPath::Tbdr,
        RenderPath::Deferred,
        RenderPath::Visibility,
    ] {
        let (mean, p99) = differences(&prez, &render(&scene, path));
        assert!(
            mean <= 0.3 && p99 <= 4,
            "{path:?}: mean {mean:.3}, p99 {p99}"
        );
    }
}

#[test]
fn a_minimap_view_renders_in_the_same_frame_and_leaves_the_main_view_alone() {
    use renderer::frame::{FrameCamera, ViewTarget};
    let gpu = engine_device();
    let program = MaterialProgram::new(&engine_shaders::bricks::MODULE).expect("a material");
    let scene = bricked_yard();
    let config = RendererConfig {
        width: WIDTH,
        height: HEIGHT,
        path: RenderPath::Clustered,
        ..Default::default()
    };
    let new_renderer = || {
        let mut r = Renderer::new(&gpu, config).expect("the renderer");
        r.register_material(program)
            .expect("the engine's material registers");
        r.prepare_scene(&scene).expect("the scene fits");
        r.set_lights(&lights()).expect("the lights fit");
        r
    };
    let mut alone = new_renderer();
    let single = frame(&gpu, &mut alone, &scene);

    let mut renderer = new_renderer();
    let minimap_config = RendererConfig {
        width: 64,
        height: 64,
        msaa: 1,
        path: RenderPath::Tiled,
        ..config
    };
    let minimap = renderer.add_view(minimap_config).expect("the minimap view");
    let above =
        glam::camera::rh::view::look_at_mat4(Vec3::new(0.0, 20.0, 0.0), Vec3::ZERO, Vec3::NEG_Z);
    let minimap_camera = FrameCamera::orthographic(above.inverse(), (7.0, 7.0), (1.0, 40.0));
    let main_target = create_target(gpu.device(), renderer.config());
    let minimap_target = create_target(gpu.device(), &minimap_config);
    let camera = framing_camera(scene.bounds, WIDTH as f32 / HEIGHT as f32);
    let views = [ViewTarget {
        view: minimap,
        camera: &minimap_camera,
        target: &minimap_target,
    }];
    let report = renderer
        .render_views(&camera, &main_target, &views)
        .expect("a frame of two views");
    renderer.finish();
    assert_eq!(report.views.len(), 1);
    assert!(
        report.views[0].shadows.is_none(),
        "one shadow atlas for both views"
    );
    let read = |t| readback::read_texture_rgba8(gpu.device(), gpu.queue(), t).expect("readback");
    assert_eq!(
        read(&main_target),
        single,
        "the minimap changed the main view"
    );
    let map = read(&minimap_target);
    let ground = map
        .chunks(4)
        .filter(|p| p[0] > 24 || p[1] > 24 || p[2] > 24)
        .count();
    assert!(
        ground > 64 * 64 / 2,
        "the minimap sees the lit yard: {ground} pixels"
    );
}
