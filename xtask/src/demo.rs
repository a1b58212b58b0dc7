//! `cargo xtask demo`: the main job. Renders a glTF scene with procedural lights through the
//! frame graph (pre-Z → light culling → Forward+ → tonemap) and writes a PNG.

use std::path::PathBuf;

use anyhow::{Context as _, Result};
use renderer::frame::setup::{framing_camera, procedural_lights};
use renderer::frame::{RenderPath, Renderer, RendererConfig};
use renderer::scene::Scene;
use renderer::{GpuContext, GpuOptions, readback};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Use the adapter whose name contains this (case-insensitive); also `RENDERER_ADAPTER`.
    #[arg(long)]
    adapter: Option<String>,
    /// glTF scene; defaults to the committed tests/scenes/AlphaBlendModeTest.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Procedural lights added to the scene's own.
    #[arg(long, default_value_t = 1024)]
    lights: usize,
    /// Frame size, WxH.
    #[arg(long, default_value = "640x360")]
    size: String,
    /// Output PNG; defaults to target/demo/frame.png.
    #[arg(long)]
    out: Option<PathBuf>,
}

#[expect(clippy::print_stdout, reason = "a command-line report")]
pub fn run(args: &Args) -> Result<()> {
    let (w, h) = args
        .size
        .split_once('x')
        .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)))
        .filter(|&(w, h)| (1..=8192).contains(&w) && (1..=8192).contains(&h))
        .context("--size must be WxH with each side 1..=8192, for example 640x360")?;
    let root = crate::workspace_root();
    let scene_path = args
        .scene
        .clone()
        .unwrap_or_else(|| root.join("tests/scenes/AlphaBlendModeTest/AlphaBlendModeTest.glb"));
    let scene = Scene::load(&scene_path)?;
    let options = GpuOptions::from_env().with_adapter_name(args.adapter.clone());
    let gpu = GpuContext::new_blocking(&options)?;
    println!("adapter: {}", gpu.report);
    let msaa = if gpu.capabilities().msaa_counts().contains(&4) {
        4
    } else {
        1
    };
    let config = RendererConfig {
        width: w,
        height: h,
        msaa,
        path: RenderPath::Tiled,
        ..Default::default()
    };
    let mut renderer = Renderer::new(&gpu, config)?;
    renderer.prepare_scene(&scene);
    let size = (scene.bounds.max - scene.bounds.min).length();
    let mut lights = scene.lights.clone();
    lights.extend(procedural_lights(
        scene.bounds,
        args.lights,
        1,
        size * 0.03,
        size * 0.2,
    ));
    renderer.set_lights(&lights);
    let target = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("demo target"),
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
    let report = renderer.render(&camera, &target)?;
    let timings = renderer.finish();
    let rgba = readback::read_texture_rgba8(&gpu.device, &gpu.queue, &target)?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| root.join("target/demo/frame.png"));
    if let Some(dir) = out.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    image::save_buffer(&out, &rgba, w, h, image::ExtendedColorType::Rgba8)
        .with_context(|| format!("writing {}", out.display()))?;
    println!(
        "scene {} ({} triangles), {} lights, {w}x{h}, MSAA {msaa}, Forward+ tiled 16x16",
        scene_path.display(),
        scene.triangle_count(),
        lights.len()
    );
    println!(
        "CPU: build + compile + encode the frame graph: {:.3} ms",
        report.cpu_graph_ms
    );
    match timings {
        Some(t) => {
            for pass in &t {
                println!("GPU {:<14} {:8.3} ms", pass.pass, pass.gpu_ms);
            }
        }
        None => println!("GPU time: unavailable (no timestamp queries on this adapter)"),
    }
    println!("wrote {}", out.display());
    Ok(())
}
