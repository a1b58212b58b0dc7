//! `cargo xtask render`: one frame of a glTF scene with every renderer option on the command
//! line, written to a PNG, with per-pass GPU timings. `cargo xtask demo` is a preset of it.

use std::path::PathBuf;

use anyhow::{Context as _, Result, bail};
use glam::Vec3;
use renderer::frame::setup::{create_target, framing_camera, procedural_lights, scene_camera};
use renderer::frame::{FrameCamera, FrameView, Renderer, RendererConfig};
use renderer::scene::Scene;
use renderer::{GpuContext, GpuOptions, readback};

use crate::bench::matrix::{PathChoice, parse_size};

#[derive(Debug, Clone, clap::Args)]
pub struct Args {
    /// glTF scene (.gltf or .glb); without it, the committed tests/scenes/AlphaBlendModeTest.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Procedural point lights added to the scene's own.
    #[arg(long, default_value_t = 1024)]
    pub lights: usize,
    /// Seed of the procedural lights.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Range of light radii in scene units, MIN,MAX (0 < MIN <= MAX); defaults to 3%..20% of
    /// the scene's size.
    #[arg(long, value_parser = parse_radius_range)]
    pub light_radius: Option<(f32, f32)>,
    /// naive | naive-prez | tiled | 2.5d | clustered (naive: every light at every fragment, no
    /// pre-pass; naive-prez: the same after a depth pre-pass).
    #[arg(long, default_value = "tiled")]
    pub path: String,
    /// MSAA sample count: 1, 2, 4 or 8 (as the adapter supports).
    #[arg(long, default_value_t = 4)]
    pub msaa: u32,
    /// Frame size, WxH.
    #[arg(long, default_value = "640x360")]
    pub size: String,
    /// Tile size of the tiled paths: 8, 16 or 32.
    #[arg(long, default_value_t = 16)]
    pub tile: u32,
    /// auto | on | off: subgroup (scalarized) variants; auto uses them when SUBGROUP exists.
    #[arg(long, default_value = "auto")]
    pub scalarize: String,
    /// Use the scene's camera with this index.
    #[arg(long, conflicts_with_all = ["eye", "target"])]
    pub camera: Option<usize>,
    /// Camera position X,Y,Z (with --target); default: a camera framing the scene's bounds.
    #[arg(long, value_parser = parse_vec3, requires = "target")]
    pub eye: Option<Vec3>,
    /// Point the camera looks at, X,Y,Z (with --eye).
    #[arg(long, value_parser = parse_vec3, requires = "eye")]
    pub target: Option<Vec3>,
    /// lit | heatmap: the shaded image, or the light count of each pixel's list with a legend.
    #[arg(long, default_value = "lit")]
    pub view: String,
    /// Output PNG; defaults to target/render/frame.png.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Adapter name substring (also RENDERER_ADAPTER).
    #[arg(long)]
    pub adapter: Option<String>,
}

#[expect(clippy::print_stdout, reason = "a command-line report")]
pub fn run(args: &Args, default_out: &str) -> Result<()> {
    let (w, h) = parse_size(&args.size)?;
    let path = PathChoice::parse(&args.path)?.0;
    let root = crate::workspace_root();
    let scene_path = args
        .scene
        .clone()
        .unwrap_or_else(|| root.join("tests/scenes/AlphaBlendModeTest/AlphaBlendModeTest.glb"));
    let scene = Scene::load(&scene_path)?;
    let gpu =
        GpuContext::new_blocking(&GpuOptions::from_env().with_adapter_name(args.adapter.clone()))?;
    let scalarize = match args.scalarize.as_str() {
        "auto" => gpu.capabilities().subgroup.is_some(),
        "on" => true,
        "off" => false,
        other => bail!("--scalarize {other:?}: use auto, on or off"),
    };
    let view = match args.view.as_str() {
        "lit" => FrameView::Lit,
        "heatmap" => FrameView::Heatmap,
        other => bail!("--view {other:?}: use lit or heatmap"),
    };
    println!("adapter: {}", gpu.report);
    let config = RendererConfig {
        width: w,
        height: h,
        msaa: args.msaa,
        path,
        tile: args.tile,
        scalarize,
        view,
        ..Default::default()
    };
    let mut renderer = Renderer::new(&gpu, config)?;
    renderer.prepare_scene(&scene);
    let size = (scene.bounds.max - scene.bounds.min).length();
    let (rmin, rmax) = args.light_radius.unwrap_or((size * 0.03, size * 0.2));
    let mut lights = scene.lights.clone();
    lights.extend(procedural_lights(
        scene.bounds,
        args.lights,
        args.seed,
        rmin,
        rmax,
    ));
    renderer.set_lights(&lights);
    let camera = pick_camera(args, &scene, w as f32 / h as f32)?;
    let target = create_target(&gpu.device, &config);
    let report = renderer.render(&camera, &target)?;
    let timings = renderer.finish();
    let rgba = readback::read_texture_rgba8(&gpu.device, &gpu.queue, &target)?;
    let out = args.out.clone().unwrap_or_else(|| root.join(default_out));
    if let Some(dir) = out.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    image::save_buffer(&out, &rgba, w, h, image::ExtendedColorType::Rgba8)
        .with_context(|| format!("writing {}", out.display()))?;
    println!(
        "scene {} ({} triangles), {} lights, {w}x{h}, MSAA {}, path {}, tile {}, scalarize {scalarize}",
        scene_path.display(),
        scene.triangle_count(),
        lights.len(),
        args.msaa,
        args.path,
        args.tile
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
    if let Some(c) = renderer.culling_counters() {
        println!(
            "culling: {} list entries, most items in one cell {}, {} cells over the per-cell limit, {} entries dropped",
            c.requested_entries, c.max_cell_items, c.overflow_cells, c.dropped
        );
        if c.dropped > 0 {
            println!(
                "WARNING: lights were dropped from some lists this frame: the image is not exact (see above)"
            );
        }
    }
    println!("compiled frame graph:\n{}", report.graph_dot);
    println!("wrote {}", out.display());
    Ok(())
}

fn pick_camera(args: &Args, scene: &Scene, aspect: f32) -> Result<FrameCamera> {
    let size = (scene.bounds.max - scene.bounds.min).length().max(1e-3);
    if let Some(i) = args.camera {
        let Some(c) = scene.cameras.get(i) else {
            bail!(
                "--camera {i}: the scene has {} camera(s)",
                scene.cameras.len()
            );
        };
        return Ok(scene_camera(
            c.world_from_view,
            c.yfov,
            aspect,
            c.znear,
            c.zfar.unwrap_or(size * 10.0),
        ));
    }
    if let (Some(eye), Some(target)) = (args.eye, args.target) {
        let (near, far) = (size * 0.01, size * 10.0);
        let world_from_view = glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y).inverse();
        return Ok(scene_camera(
            world_from_view,
            45f32.to_radians(),
            aspect,
            near,
            far,
        ));
    }
    Ok(framing_camera(scene.bounds, aspect))
}

/// Comma-separated finite numbers, exactly `N` of them.
fn parse_numbers<const N: usize>(s: &str, what: &str) -> Result<[f32; N], String> {
    let values: Vec<f32> = s
        .split(',')
        .map(|v| v.trim().parse::<f32>().ok().filter(|v| v.is_finite()))
        .collect::<Option<_>>()
        .ok_or_else(|| format!("{s:?} is not {what}"))?;
    values
        .try_into()
        .map_err(|_| format!("{s:?} is not {what}"))
}

/// `MIN,MAX` with `0 < MIN <= MAX`.
fn parse_radius_range(s: &str) -> Result<(f32, f32), String> {
    let [min, max] = parse_numbers::<2>(s, "MIN,MAX (two numbers, e.g. 0.5,3)")?;
    if min > 0.0 && min <= max {
        Ok((min, max))
    } else {
        Err(format!("{s:?}: give MIN,MAX with 0 < MIN <= MAX"))
    }
}

/// `X,Y,Z`.
fn parse_vec3(s: &str) -> Result<Vec3, String> {
    parse_numbers::<3>(s, "X,Y,Z (three numbers, e.g. 0,2,5)").map(Vec3::from_array)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radius_ranges_and_points_parse_as_documented() {
        assert_eq!(parse_radius_range("50,200"), Ok((50.0, 200.0)));
        assert_eq!(parse_radius_range(" 0.5 , 3 "), Ok((0.5, 3.0)));
        for bad in ["50", "50,200,300", "0,1", "2,1", "a,b", "1,inf", ""] {
            assert!(parse_radius_range(bad).is_err(), "{bad:?} must be refused");
        }
        assert_eq!(parse_vec3("0,2,-5"), Ok(Vec3::new(0.0, 2.0, -5.0)));
        assert!(parse_vec3("1,2").is_err());
        assert!(parse_vec3("1,2,NaN").is_err());
    }
}
