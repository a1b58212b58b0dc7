//! `cargo xtask bench-particles --lighting`: whole frames of the demo scene with particles lit
//! through the atlas against the same particles lit per pixel, at heavy overdraw: per-pass GPU
//! medians, the particles' overdraw (billboard area over screen area) and the difference of
//! the two images.

use std::collections::BTreeMap;

use anyhow::{Context as _, Result};
use glam::Vec3;
use renderer::frame::create_target;
use renderer::frame::{FrameView, ParticleLighting, Renderer, RendererConfig};
use renderer::passes::particles::ParticleSimPass;
use renderer::readback;

use crate::bench::calibrate::percentile;
use renderer::particles::WARMUP_STEPS;

use crate::render::{Setup, setup};

/// The particle passes each lighting runs, and what both share.
const PARTICLE_PASSES: [&str; 4] = [
    "particle simulation",
    "particle layout",
    "particle lighting",
    "particles",
];

/// What to measure: particle counts, timed frames, and the frames' path, size, lights and
/// camera (`smoke` or `scene`).
#[derive(Debug, Clone)]
pub struct Bench {
    pub counts: Vec<u32>,
    pub frames: u32,
    pub path: String,
    pub size: String,
    pub lights: usize,
    pub camera: String,
}

/// One lighting's frames: per-pass medians (ms), the last frame's pixels.
struct Run {
    medians: BTreeMap<String, f64>,
    rgba: Vec<u8>,
}

/// The demo scene (by default at 1080p, MSAA 4, 4,096 lights) with `count` particles, the
/// camera close to the smoke so that it fills the view (`smoke`), or the scene's own (`scene`).
fn scene(count: u32, bench: &Bench) -> Result<Setup> {
    let in_smoke = match bench.camera.as_str() {
        "smoke" => true,
        "scene" => false,
        other => anyhow::bail!("--lighting-camera {other:?}: use smoke or scene"),
    };
    let args = crate::render::Args {
        scene: None,
        lights: bench.lights,
        shadowed: 16,
        shadow_atlas: 4096,
        seed: 1,
        decals: 0,
        decals_file: None,
        particles: count,
        particle_lighting: "atlas".into(),
        vis_raster: "hardware".into(),
        particle_atlas: 0,
        light_radius: None,
        path: bench.path.clone(),
        msaa: 4,
        size: bench.size.clone(),
        tile: 16,
        scalarize: "off".into(),
        camera: None,
        eye: in_smoke.then_some(Vec3::new(-1.5, 2.0, 2.5)),
        target: in_smoke.then_some(Vec3::new(-4.2, 1.6, -2.3)),
        view: "lit".into(),
        exposure: None,
        ambient: None,
        out: None,
        adapter: None,
        msaa_fallback: false,
        no_cull_draws: false,
        no_occlusion: false,
    };
    setup(&args)
}

fn run_lighting(s: &Setup, lighting: ParticleLighting, frames: u32) -> Result<(Run, f64)> {
    let config = RendererConfig {
        particle_lighting: lighting,
        view: FrameView::Lit,
        ..s.config
    };
    let mut renderer = Renderer::new(&s.gpu, config)?;
    renderer.prepare_scene(&s.scene)?;
    renderer.set_lights(&s.lights)?;
    let system = s.particles.as_ref().context("the bench has particles")?;
    renderer.set_particles(system, WARMUP_STEPS)?;
    let target = create_target(s.gpu.device(), &config);
    let mut times: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    // Two frames to build everything and grow the lists, then the timed ones.
    for frame in 0..frames + 2 {
        renderer.render(&s.camera, &target)?;
        renderer.wait_for_frames_in_flight(1)?;
        for t in renderer.drain_timings().into_iter().flatten() {
            if frame >= 2 {
                times.entry(t.pass).or_default().push(t.gpu_ms);
            }
        }
    }
    if let Some(last) = renderer.finish() {
        for t in last {
            times.entry(t.pass).or_default().push(t.gpu_ms);
        }
    }
    let medians: BTreeMap<String, f64> = times
        .into_iter()
        .map(|(pass, mut t)| {
            t.sort_by(f64::total_cmp);
            (pass, percentile(&t, 0.5))
        })
        .collect();
    let overdraw = overdraw(&renderer, s)?;
    let rgba = readback::read_texture_rgba8(s.gpu.device(), s.gpu.queue(), &target)?;
    Ok((Run { medians, rgba }, overdraw))
}

/// Billboard pixels per screen pixel: every live particle's projected square, clipped to the
/// screen, summed, over the screen's area.
fn overdraw(renderer: &Renderer, s: &Setup) -> Result<f64> {
    let pass = renderer
        .pass::<ParticleSimPass>()
        .and_then(ParticleSimPass::system)
        .context("the particle pass ran")?;
    let alive = pass.sim.read_alive(&s.gpu)?;
    let emitters = &pass.sim.system().emitters;
    let (w, h) = (s.config.width as f64, s.config.height as f64);
    let camera = &s.camera;
    let clip_from_world = camera.projection * camera.view;
    let mut covered = 0.0;
    for p in &alive {
        let e = &emitters[p.emitter as usize];
        let life = (p.age / p.lifetime).clamp(0.0, 1.0);
        let half = e.size[0] + (e.size[1] - e.size[0]) * life;
        let clip = clip_from_world * p.position.extend(1.0);
        if clip.w <= camera.near {
            continue;
        }
        let centre = (
            (f64::from(clip.x / clip.w) * 0.5 + 0.5) * w,
            (0.5 - f64::from(clip.y / clip.w) * 0.5) * h,
        );
        let r = f64::from(half * camera.projection.y_axis.y / clip.w) * h * 0.5;
        let span = |c: f64, size: f64| ((c + r).min(size) - (c - r).max(0.0)).max(0.0);
        covered += span(centre.0, w) * span(centre.1, h);
    }
    Ok(covered / (w * h))
}

/// The Markdown table of atlas against per-pixel lighting at each particle count.
#[expect(clippy::print_stdout, reason = "command-line report")]
pub fn table(bench: &Bench) -> Result<String> {
    let frames = bench.frames;
    let mut out = String::from(
        "| particles | overdraw | layout + sort (ms) | atlas: lighting (ms) | atlas: draw (ms) | atlas total (ms) | per-pixel: draw (ms) | per-pixel ÷ atlas | forward (ms) | image: mean, p99 |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for &count in &bench.counts {
        let s = scene(count, bench)?;
        let (atlas, overdraw) = run_lighting(&s, ParticleLighting::Atlas, frames)?;
        let (pixel, _) = run_lighting(&s, ParticleLighting::PerPixel, frames)?;
        let ms = |r: &Run, pass: &str| r.medians.get(pass).copied().unwrap_or(0.0);
        let layout = ms(&atlas, PARTICLE_PASSES[1]);
        let atlas_total = ms(&atlas, PARTICLE_PASSES[2]) + ms(&atlas, PARTICLE_PASSES[3]);
        let (mean, p99) = crate::render::difference(&atlas.rgba, &pixel.rgba);
        let row = format!(
            "| {count} | {overdraw:.1} | {layout:.3} | {:.3} | {:.3} | {atlas_total:.3} | {:.3} | {:.1}× | {:.3} | {mean:.2}, {p99} |",
            ms(&atlas, PARTICLE_PASSES[2]),
            ms(&atlas, PARTICLE_PASSES[3]),
            ms(&pixel, PARTICLE_PASSES[3]),
            ms(&pixel, PARTICLE_PASSES[3]) / atlas_total.max(1e-9),
            ms(&atlas, "forward"),
        );
        println!("{row}");
        out.push_str(&row);
        out.push('\n');
    }
    Ok(out)
}
