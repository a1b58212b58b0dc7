//! `cargo xtask render`: one frame of a glTF scene with every renderer option on the command
//! line, written to a PNG, with per-pass GPU timings. `cargo xtask demo` is a preset of it.

use std::path::PathBuf;

use anyhow::{Context as _, Result, bail};
use glam::Vec3;
use renderer::culling::lists::CullCounters;
use renderer::decals::DecalSet;
use renderer::demo::{courtyard_look, pick_shadowed, procedural_lights};
use renderer::frame::create_target;
use renderer::frame::{
    FrameCamera, FrameReport, FrameView, ParticleLighting, RenderPath, Renderer, RendererConfig,
    VisibilityRaster,
};
use renderer::frame_data::LightSet;
use renderer::graph::PassTiming;
use renderer::particles::{ParticleSystem, WARMUP_STEPS, builtin_system};
use renderer::passes::particles::ParticleSimulation;
use renderer::scene::{Scene, SceneLight};

use renderer::{GpuContext, GpuOptions, readback};

use crate::bench::matrix::{PathChoice, parse_size};

#[cfg(test)]
mod cli_tests;
mod output;
mod parse;
pub mod scene_arg;

pub use scene_arg::BUILTIN_SCENE;

pub use output::{difference, draws_line, particle_summary, save_png, save_text, shadow_summary};
pub(crate) use parse::parse_exposure;
use parse::{parse_ambient, parse_radius_range, parse_vec3};

#[derive(Debug, Clone, clap::Args)]
pub struct Args {
    /// glTF scene (.gltf or .glb), `city:N` for a generated city of N instances; without it (or
    /// with `courtyard`), the built-in courtyard.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Procedural point lights added to the scene's own.
    #[arg(long, default_value_t = 1024)]
    pub lights: usize,
    /// Of the procedural lights, this many (those covering the most of the screen) cast shadows;
    /// the scene's own lights always do.
    #[arg(long, default_value_t = 0)]
    pub shadowed: usize,
    /// Side of the shadow atlas in texels (a power of two up to the device's largest texture).
    #[arg(long, default_value_t = 4096)]
    pub shadow_atlas: u32,
    /// Seed of the procedural lights and decals.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Procedural decals (the built-in scorch, stain and sign materials) scattered over the
    /// scene's surfaces by area.
    #[arg(long, default_value_t = 0)]
    pub decals: usize,
    /// JSON decal file (materials from PNG files or the built-ins, and placed decals); the
    /// procedural `--decals` are added to it.
    #[arg(long)]
    pub decals_file: Option<PathBuf>,
    /// Particles: about this many live at once from the built-in smoke, sparks and dust placed
    /// in the scene (a pool of this many slots), simulated for 5 s before the frame; 0: none.
    #[arg(long, default_value_t = 0)]
    pub particles: u32,
    /// atlas | per-pixel: particles lit once per frame into the lighting atlas, or per pixel
    /// (the reference).
    #[arg(long, default_value = "atlas")]
    pub particle_lighting: String,
    /// auto | hardware | compute: what rasterises the visibility path's opaque triangles
    /// (compute: kernels with 64-bit atomics, on adapters with them; auto: compute where the
    /// adapter has them, else hardware).
    #[arg(long, default_value = "auto")]
    pub vis_raster: String,
    /// Side of the particle lighting atlas in texels (a power of two); 0: 2048, or more when
    /// the pool needs it.
    #[arg(long, default_value_t = 0)]
    pub particle_atlas: u32,
    /// Range of light radii in scene units, MIN,MAX (0 < MIN <= MAX); defaults to 0.8,2.6 in
    /// the courtyard, 3%..20% of a file scene's size.
    #[arg(long, value_parser = parse_radius_range)]
    pub light_radius: Option<(f32, f32)>,
    /// naive | naive-prez | tiled | 2.5d | clustered | tbdr | tbdr-per-sample | deferred
    /// (naive: every light at every fragment, no pre-pass; naive-prez: the same after a depth
    /// pre-pass; tbdr: tile-based deferred shading in compute, tbdr-per-sample with the edge
    /// pixels' samples drained from a tile list; deferred: traditional deferred shading, a
    /// light volume per light).
    #[arg(long, default_value = "tiled")]
    pub path: String,
    /// MSAA sample count: 1, 2, 4 or 8 (as the adapter supports).
    #[arg(long, default_value_t = 4)]
    pub msaa: u32,
    /// Frame size, WxH.
    #[arg(long, default_value = "640x360")]
    pub size: String,
    /// Tile size of the culled paths (tiled, 2.5D, clustered froxels): 8, 16 or 32.
    #[arg(long, default_value_t = 16)]
    pub tile: u32,
    /// auto | on | off: the scalarized forward shader; auto uses it where a benchmark recorded
    /// it faster for this adapter (`renderer::gpu::SCALARIZE_RECORDS`) and SUBGROUP exists.
    #[arg(long, default_value = "auto")]
    pub scalarize: String,
    /// Use the scene's camera with this index.
    #[arg(long, conflicts_with_all = ["eye", "target"])]
    pub camera: Option<usize>,
    /// Camera position X,Y,Z (with --target); default: the scene's first camera, else one
    /// framing the scene's bounds.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_vec3, requires = "target")]
    pub eye: Option<Vec3>,
    /// Point the camera looks at, X,Y,Z (with --eye).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_vec3, requires = "eye")]
    pub target: Option<Vec3>,
    /// Exposure in stops (EV, the HDR colour is scaled by 2^EV before the ACES tonemap);
    /// defaults to a value calibrated for the courtyard, 0 for file scenes.
    #[arg(long, allow_negative_numbers = true, value_parser = parse_exposure)]
    pub exposure: Option<f32>,
    /// Ambient light, linear RGB: SKY:GROUND (each R,G,B; the sky lights surfaces facing up,
    /// the ground those facing down, blended in between), one R,G,B for both, or `off`.
    /// Defaults to 0.3 (sky) over 0.1 (ground) grey for file scenes, the courtyard's own.
    #[arg(long, value_parser = parse_ambient)]
    pub ambient: Option<renderer::frame::Ambient>,
    /// lit | heatmap | decals | shadow-atlas | particle-atlas: the shaded image, the light (or
    /// decal) count of each pixel's list with a legend, the shadow atlas (depth as grey, regions
    /// outlined and labelled with their light and side), or the particle lighting atlas (fitted
    /// to the frame's shorter side; needs --particles).
    #[arg(long, default_value = "lit")]
    pub view: String,
    /// Output PNG; defaults to target/render/frame.png.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Adapter name substring (also RENDERER_ADAPTER).
    #[arg(long)]
    pub adapter: Option<String>,
    /// Fall back to MSAA 1 where the adapter lacks the asked count (the demo's choice).
    #[arg(skip)]
    pub msaa_fallback: bool,
    /// Draw every draw of the scene, without GPU culling against the view (the frame is the
    /// same; for comparison).
    #[arg(long)]
    pub no_cull_draws: bool,
    /// Cull against the view frustum only, without two-phase occlusion culling (the frame is
    /// the same; for comparison).
    #[arg(long)]
    pub no_occlusion: bool,
}

/// A scene, its lights and its camera on a device, ready for frames of any view.
pub struct Setup {
    pub gpu: GpuContext,
    pub scene: Scene,
    /// The file, or the built-in scene's name.
    pub scene_name: String,
    pub lights: Vec<SceneLight>,
    pub camera: FrameCamera,
    pub config: RendererConfig,
    /// The file's decals and the procedural ones.
    pub decals: DecalSet,
    /// The `--particles` systems.
    pub particles: Option<ParticleSystem>,
}

/// One rendered frame and what the renderer reported about it.
pub struct Shot {
    pub rgba: Vec<u8>,
    pub report: FrameReport,
    pub timings: Option<Vec<PassTiming>>,
    pub counters: Option<CullCounters>,
    /// Lights listed ÷ lights reaching, over probed surface samples (culled paths, when asked).
    pub efficiency: Option<f64>,
    /// The frame's graph in Graphviz DOT.
    pub graph_dot: String,
}

/// Checks every option, opens the device and loads the scene. Bad input is an error naming the
/// option and what would be accepted, before anything large is allocated.
pub fn setup(args: &Args) -> Result<Setup> {
    let (w, h) = parse_size(&args.size)?;
    let path = PathChoice::parse(&args.path)?.0;
    // The TBDR kernels' tiles are 8 or 16 (one invocation per pixel).
    let tiles: &[u32] = if path.is_deferred() && path != RenderPath::Visibility {
        &[8, 16]
    } else {
        &[8, 16, 32]
    };
    if !tiles.contains(&args.tile) {
        bail!("--tile {}: --path {} takes {tiles:?}", args.tile, args.path);
    }
    if ![1, 2, 4, 8].contains(&args.msaa) {
        bail!("--msaa {}: use 1, 2, 4 or 8", args.msaa);
    }
    let view = match args.view.as_str() {
        "lit" => FrameView::Lit,
        "heatmap" => FrameView::Heatmap,
        "decals" => FrameView::DecalHeatmap,
        "shadow-atlas" => FrameView::ShadowAtlas,
        "particle-atlas" => FrameView::ParticleAtlas,
        "shading-frequency" => FrameView::ShadingFrequency,
        other => {
            bail!(
                "--view {other:?}: use lit, heatmap, decals, shadow-atlas, particle-atlas or \
                 shading-frequency"
            )
        }
    };
    if view == FrameView::ShadingFrequency && !path.is_deferred() {
        bail!("--view shading-frequency: use --path tbdr, tbdr-per-sample, deferred or visibility");
    }
    if view == FrameView::ParticleAtlas && args.particles == 0 {
        bail!("--view particle-atlas: the frame has no particles; add --particles N");
    }
    let particle_lighting: ParticleLighting = args
        .particle_lighting
        .parse()
        .map_err(|e: String| anyhow::anyhow!("--particle-lighting: {e}"))?;
    let visibility_raster: VisibilityRaster = args
        .vis_raster
        .parse()
        .map_err(|e: String| anyhow::anyhow!("--vis-raster: {e}"))?;
    if visibility_raster == VisibilityRaster::Compute && path != RenderPath::Visibility {
        bail!("--vis-raster compute: only the visibility path has it; add --path visibility");
    }
    let side = args.particle_atlas;
    if side != 0 && (!side.is_power_of_two() || !(64..=4096).contains(&side)) {
        bail!("--particle-atlas {side}: use a power of two from 64 to 4096, or 0 for the default");
    }
    if !matches!(args.scalarize.as_str(), "auto" | "on" | "off") {
        bail!("--scalarize {:?}: use auto, on or off", args.scalarize);
    }
    let opened = scene_arg::open_scene(args.scene.as_deref())?;
    let (scene, scene_name, builtin) = (opened.scene, opened.name, opened.courtyard);
    let gpu =
        GpuContext::new_blocking(&GpuOptions::from_env().with_adapter_name(args.adapter.clone()))?;
    let max = gpu.device().limits().max_texture_dimension_2d;
    if w > max || h > max {
        bail!("--size {w}x{h}: this adapter's largest texture side is {max}");
    }
    let most = LightSet::max_lights(gpu.device());
    if args.lights > most {
        bail!(
            "--lights {}: this device holds at most {most} lights",
            args.lights
        );
    }
    let counts = gpu.capabilities().msaa_counts();
    if !counts.contains(&args.msaa) && !args.msaa_fallback {
        bail!(
            "--msaa {}: this adapter supports MSAA {counts:?} for the frame's targets",
            args.msaa
        );
    }
    let scalarize = match args.scalarize.as_str() {
        "auto" => renderer::gpu::scalarize_auto(&gpu, renderer::gpu::ScalarizedKernel::Forward),
        other => other == "on",
    };
    let config = RendererConfig {
        width: w,
        height: h,
        msaa: if counts.contains(&args.msaa) {
            args.msaa
        } else {
            1
        },
        path,
        visibility_raster,
        tile: args.tile,
        scalarize,
        view,
        particle_lighting,
        particle_atlas_side: side,
        cull_draws: !args.no_cull_draws,
        occlusion_cull: !args.no_occlusion,
        ..Default::default()
    };
    let mut config = if builtin {
        courtyard_look(config)
    } else {
        config
    };
    if let Some(ev) = args.exposure {
        config.exposure = 2f32.powf(ev);
    }
    if let Some(ambient) = args.ambient {
        config.ambient = ambient;
    }
    // Lights fill the built-in courtyard's open space in pools, the city's streets around its
    // camera, a file's scene its bounds.
    let (region, default_radius) = (opened.light_region, opened.light_radii);
    let (rmin, rmax) = args.light_radius.unwrap_or(default_radius);
    let mut lights = scene.lights.clone();
    lights.extend(procedural_lights(
        region,
        args.lights,
        args.seed,
        rmin,
        rmax,
    ));
    let chosen = (args.camera, args.eye, args.target);
    let camera = scene_arg::pick_camera(chosen, &scene, w as f32 / h as f32)?;
    let decals = decal_set(args, &scene)?;
    let particles = particle_system(args, &scene, &gpu)?;
    let shadowed_from = scene.lights.len();
    pick_shadowed(
        &mut lights[shadowed_from..],
        &camera,
        h as f32,
        args.shadowed,
    );
    config.shadows.atlas_size = args.shadow_atlas;
    // Four cascades take a quarter of the atlas at most.
    config.shadows.cascade_resolution = (args.shadow_atlas / 4).clamp(64, 2048);
    Ok(Setup {
        gpu,
        scene,
        scene_name,
        lights,
        camera,
        config,
        decals,
        particles,
    })
}

/// The built-in emitters for about `--particles` live particles, validated on `gpu`.
fn particle_system(args: &Args, scene: &Scene, gpu: &GpuContext) -> Result<Option<ParticleSystem>> {
    if args.particles == 0 {
        return Ok(None);
    }
    let system = builtin_system(scene.bounds, args.particles, args.seed as u32);
    let max = ParticleSimulation::max_capacity(gpu.device());
    system
        .validate(max)
        .with_context(|| format!("--particles {}", args.particles))?;
    Ok(Some(system))
}

/// The `--decals-file` set (or the built-in materials alone) with `--decals` procedural decals
/// added, validated.
fn decal_set(args: &Args, scene: &Scene) -> Result<DecalSet> {
    let mut set = match &args.decals_file {
        Some(path) => renderer::decals::sidecar::load(path)
            .with_context(|| format!("--decals-file {}", path.display()))?,
        None => DecalSet {
            materials: renderer::decals::procedural::materials(),
            decals: Vec::new(),
        },
    };
    let scattered =
        renderer::demo::scatter_decals(scene, args.decals, set.materials.len(), args.seed);
    if scattered.len() < args.decals {
        bail!(
            "--decals {}: the scene has no surface to place them on",
            args.decals
        );
    }
    set.decals.extend(scattered);
    set.validate().context("decals")?;
    Ok(set)
}

/// Renders one frame of `view` (and measures the cull efficiency when `efficiency`).
pub fn shoot(s: &Setup, view: FrameView, efficiency: bool) -> Result<Shot> {
    shoot_with(s, RendererConfig { view, ..s.config }, efficiency)
}

/// A renderer of `config` holding the set-up's scene, lights, decals and particles.
pub fn renderer_for(s: &Setup, config: RendererConfig) -> Result<Renderer> {
    let mut renderer = Renderer::new(&s.gpu, config)?;
    renderer.prepare_scene(&s.scene)?;
    renderer.set_lights(&s.lights)?;
    renderer.set_decals(&s.decals)?;
    if let Some(p) = &s.particles {
        renderer.set_particles(p, WARMUP_STEPS)?;
    }
    Ok(renderer)
}

/// [`shoot`] with settings of its own (another path or view of the same set-up).
pub fn shoot_with(s: &Setup, config: RendererConfig, efficiency: bool) -> Result<Shot> {
    let mut renderer = renderer_for(s, config)?;
    let target = create_target(s.gpu.device(), &config);
    if efficiency {
        renderer.capture_next_frame(4)?;
    }
    let mut report = renderer.render(&s.camera, &target)?;
    let timings = renderer.finish();
    // The culled count arrives after the frame: the last frame's, now that it finished.
    report.scene_draws = renderer.scene_draws().or(report.scene_draws);
    report.shadows = renderer.shadow_report().or(report.shadows);
    let counters = renderer.culling_counters();
    if let Some(c) = counters {
        // The renderer sizes its lists before the frame; a drop means they outgrew one storage
        // binding, and a frame with lights missing is never written.
        anyhow::ensure!(
            c.dropped == 0,
            "light culling dropped {} of {} list entries (the lists outgrow one storage binding \
             on this device): the frame is not exact and was not written; use the clustered or \
             2.5D path, a larger tile, smaller radii or fewer lights",
            c.dropped,
            c.requested_entries
        );
    }
    report.particles = renderer.particle_report();
    let efficiency = match renderer.take_capture()? {
        Some(capture) => {
            let surface = capture.surface_probes();
            let reaching = capture.lights_reaching(&surface);
            capture
                .cull_efficiency(&surface, &reaching)
                .map(|e| e.ratio())
        }
        None => None,
    };
    let mut rgba = readback::read_texture_rgba8(s.gpu.device(), s.gpu.queue(), &target)?;
    if let (FrameView::ShadowAtlas, Some(shadows)) = (config.view, &report.shadows) {
        let size = (config.width, config.height);
        if let Err(e) =
            crate::atlas_labels::label(&mut rgba, size, config.fitted_shadows().atlas_size, shadows)
        {
            eprintln!("note: shadow atlas labels left out: {e:#}");
        }
    }
    Ok(Shot {
        rgba,
        report,
        timings,
        counters,
        efficiency,
        graph_dot: renderer.graph_dot().unwrap_or_default(),
    })
}

#[expect(clippy::print_stdout, reason = "a command-line report")]
pub fn run(args: &Args, default_out: &str) -> Result<()> {
    crate::system::ensure_vulkan_adapter()?;
    let s = setup(args)?;
    let shot = shoot(&s, s.config.view, false)?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| crate::workspace::workspace_root().join(default_out));
    let size = (s.config.width, s.config.height);
    save_png(&out, &shot.rgba, size)?;
    let dot = out.with_extension("dot");
    save_text(&dot, &shot.graph_dot)?;
    println!("adapter: {}", s.gpu.report());
    println!(
        "scene {} ({} triangles), {} lights, {}x{}, MSAA {}, path {}, tile {}, scalarize {}",
        s.scene_name,
        s.scene.triangle_count(),
        s.lights.len(),
        size.0,
        size.1,
        s.config.msaa,
        args.path,
        s.config.tile,
        s.config.scalarize,
    );
    if let Some(d) = shot.report.scene_draws {
        println!("{}", draws_line(&d));
    }
    println!(
        "CPU: prepare {:.3} ms, build + compile + encode the frame graph {:.3} ms, submit {:.3} ms",
        shot.report.cpu_upload_ms, shot.report.cpu_graph_ms, shot.report.cpu_submit_ms
    );
    match &shot.timings {
        Some(t) => {
            for pass in t {
                println!("GPU {:<14} {:8.3} ms", pass.pass, pass.gpu_ms);
            }
        }
        None => println!("GPU time: unavailable (no timestamp queries on this adapter)"),
    }
    if let Some(r) = &shot.report.shadows {
        println!("{}", shadow_summary(r));
    }
    if let Some(p) = &shot.report.particles {
        println!("{}", particle_summary(p));
    }
    if let Some(c) = shot.counters {
        println!(
            "culling: {} list entries, longest list {}, {} super-tiles fell back to testing every light, {} entries dropped",
            c.requested_entries, c.max_cell_items, c.coarse_fallbacks, c.dropped
        );
    }
    println!(
        "wrote {} and the frame graph {}",
        out.display(),
        dot.display()
    );
    Ok(())
}
