//! What the arguments select: the scenes, the matrix axes, the shadow axis and each set-up's
//! renderer configuration.

use anyhow::Result;
use renderer::frame::RendererConfig;
use renderer::scene::{Aabb, Scene};

use super::Args;
use super::matrix::{self, Axes, PathChoice, Setup};
use super::shadows::{ShadowAxes, ShadowKind, ShadowMode};

pub(super) struct BenchScene {
    pub(super) name: String,
    pub(super) scene: Scene,
    /// Where the moving lights go: the scene's bounds, or a generated city's streets around
    /// its camera (a city's bounds grow with its size; its lit streets do not).
    pub(super) light_box: Aabb,
}

pub(super) fn load_scenes(args: &Args) -> Result<Vec<BenchScene>> {
    let mut scenes = Vec::new();
    if !args.no_demo_scene {
        let scene = renderer::scene::procedural::courtyard();
        scenes.push(BenchScene {
            name: crate::render::BUILTIN_SCENE.to_string(),
            light_box: scene.bounds,
            scene,
        });
    }
    for p in &args.scene {
        let opened = crate::render::scene_arg::open_scene(Some(p))?;
        let name = if opened.generated || opened.courtyard {
            opened.name
        } else {
            p.file_stem()
                .map_or("scene".into(), |s| s.to_string_lossy().into_owned())
        };
        let light_box = if opened.generated {
            opened.light_region
        } else {
            opened.scene.bounds
        };
        scenes.push(BenchScene {
            name,
            scene: opened.scene,
            light_box,
        });
    }
    anyhow::ensure!(
        !scenes.is_empty(),
        "no scene: drop --no-demo-scene or give --scene FILE"
    );
    Ok(scenes)
}

pub(super) fn axes(args: &Args, scenes: &[BenchScene]) -> Result<Axes> {
    let mut axes = Axes {
        scenes: scenes.iter().map(|s| s.name.clone()).collect(),
        sizes: parse_list(&args.sizes, matrix::parse_size)?,
        msaa: args.msaa.clone(),
        paths: parse_list(&args.paths, PathChoice::parse)?,
        tiles: args.tiles.clone(),
        scalarize: parse_list(&args.scalarize, matrix::parse_on_off)?,
        brute_force: parse_list(&args.cull, matrix::parse_cull)?,
        lights: args.lights.clone(),
    };
    if args.quick {
        axes.sizes = vec![(256, 144), (384, 216)];
        axes.lights = vec![64, 256, 1024, 4096];
    }
    for &t in &axes.tiles {
        anyhow::ensure!([8, 16, 32].contains(&t), "tile {t}: use 8, 16 or 32");
    }
    anyhow::ensure!(
        axes.lights.iter().all(|&n| n > 0),
        "light counts must be positive"
    );
    Ok(axes)
}

/// Every value of a list option, parsed; the first bad one is the error.
fn parse_list<T>(values: &[String], parse: impl Fn(&str) -> Result<T>) -> Result<Vec<T>> {
    values.iter().map(|v| parse(v)).collect()
}

/// The shadow axis; empty without `--shadowed`.
pub(super) fn shadow_axes(args: &Args, axes: &Axes) -> Result<ShadowAxes> {
    let fewest = axes.lights.iter().copied().min().unwrap_or(0);
    for &n in &args.shadowed {
        anyhow::ensure!(
            n <= fewest,
            "--shadowed {n}: more than the {fewest} lights of --lights; give --lights {n} or more"
        );
    }
    Ok(ShadowAxes {
        counts: args.shadowed.clone(),
        kinds: parse_list(&args.shadow_kinds, ShadowKind::parse)?,
        modes: parse_list(&args.shadow_modes, ShadowMode::parse)?,
    })
}

/// The renderer configuration of a set-up.
pub(super) fn renderer_config(args: &Args, setup: &Setup) -> RendererConfig {
    let mut config = RendererConfig {
        width: setup.width,
        height: setup.height,
        msaa: setup.msaa,
        path: setup.path.0,
        visibility_raster: setup.path.1,
        tile: setup.tile.max(8),
        scalarize: setup.scalarize,
        cull_brute_force: setup.brute_force,
        time_cull_dispatches: args.cull_dispatch_times,
        cull_draws: !args.no_cull_draws,
        occlusion_cull: !args.no_occlusion,
        compute_tonemap: !args.fragment_tonemap,
        ..Default::default()
    };
    config.shadows.atlas_size = args.shadow_atlas;
    config
}
