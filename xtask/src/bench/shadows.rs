//! The shadow axis of `cargo xtask bench` (`--shadowed 16,64,256`): what shadowed lights cost,
//! per pass, when nothing moves (every region cached), when one object moves, when every light
//! moves, and with the cache turned off, beside the same frame without shadows.
//!
//! Each cell takes the run's procedural lights, marks the `shadowed` that cover the most of the
//! screen as casters (as `cargo xtask render --shadowed` does), turns them into spot lights
//! pointing down for `--shadow-kinds spot`, and marks one object dynamic (the courtyard's last
//! sphere) in every mode, so that the modes differ only in what moves.

use std::fmt::Write as _;

use anyhow::{Context as _, Result, bail};
use glam::{Mat4, Vec3};
use renderer::demo::{moving_instance, pick_shadowed};
use renderer::frame::{FrameCamera, Renderer};
use renderer::frame::{create_target, default_camera};
use renderer::scene::{LightKind, Scene, SceneLight};
use renderer::{GpuContext, frame::RendererConfig};

use super::lights::MovingLights;
use super::matrix::Setup;
use super::measure::{self, FramePlan};
use super::record::{CellRecord, ms};

/// What the shadowed lights are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShadowKind {
    /// Six cube faces each.
    Point,
    /// One region each: the shadowed lights become spot lights pointing down.
    Spot,
}

impl ShadowKind {
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "point" => Ok(Self::Point),
            "spot" => Ok(Self::Spot),
            other => bail!("shadow kind {other:?}: use point, spot or point,spot"),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Point => "point",
            Self::Spot => "spot",
        }
    }
}

/// What changes between the frames of a cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShadowMode {
    /// No light casts a shadow (the baseline the others are compared with).
    None,
    /// Nothing moves: after the first frame every region is cached.
    Static,
    /// One dynamic object moves every frame: only the regions it reaches are recomposed.
    Moving,
    /// Every light moves every frame: every region is redrawn.
    LightsMoving,
    /// Nothing moves, but the cache is off: every region is redrawn every frame.
    Uncached,
}

impl ShadowMode {
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "static" => Ok(Self::Static),
            "moving" => Ok(Self::Moving),
            "lights-moving" => Ok(Self::LightsMoving),
            "uncached" => Ok(Self::Uncached),
            other => {
                bail!("shadow mode {other:?}: use static, moving, lights-moving or uncached")
            }
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Static => "static",
            Self::Moving => "moving",
            Self::LightsMoving => "lights-moving",
            Self::Uncached => "uncached",
        }
    }
}

/// The shadow axis of a run.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ShadowAxes {
    /// Shadowed light counts; 0 is the baseline without shadows.
    pub counts: Vec<u32>,
    pub kinds: Vec<ShadowKind>,
    pub modes: Vec<ShadowMode>,
}

/// One cell of the shadow axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShadowCell {
    pub shadowed: u32,
    pub kind: ShadowKind,
    pub mode: ShadowMode,
}

impl ShadowCell {
    pub fn label(self) -> String {
        match self.mode {
            ShadowMode::None => "no shadows".into(),
            m => format!("{} {} {}", self.shadowed, self.kind.name(), m.name()),
        }
    }
}

/// The cells of `axes`: one baseline for a count of 0, every kind × mode for the others; empty
/// without `--shadowed`.
pub fn cells(axes: &ShadowAxes) -> Vec<ShadowCell> {
    let mut cells = Vec::new();
    for &shadowed in &axes.counts {
        if shadowed == 0 {
            cells.push(ShadowCell {
                shadowed,
                kind: ShadowKind::Point,
                mode: ShadowMode::None,
            });
            continue;
        }
        for &kind in &axes.kinds {
            for &mode in &axes.modes {
                cells.push(ShadowCell {
                    shadowed,
                    kind,
                    mode,
                });
            }
        }
    }
    cells
}

/// Half-angles of the spot lights of `--shadow-kinds spot` (radians).
const SPOT_CONES: (f32, f32) = (0.6, 0.8);

/// The lights of `cell`: `lights` with those flagged in `casts` casting shadows, as spot lights
/// pointing down for [`ShadowKind::Spot`].
fn shadow_lights(cell: ShadowCell, lights: &[SceneLight], casts: &[bool]) -> Vec<SceneLight> {
    lights
        .iter()
        .zip(casts)
        .map(|(l, &casts_shadow)| match (casts_shadow, cell.kind) {
            (false, _) => *l,
            (true, ShadowKind::Point) => SceneLight { casts_shadow, ..*l },
            (true, ShadowKind::Spot) => SceneLight {
                kind: LightKind::Spot {
                    inner_cone: SPOT_CONES.0,
                    outer_cone: SPOT_CONES.1,
                },
                direction: Vec3::NEG_Y,
                casts_shadow,
                ..*l
            },
        })
        .collect()
}

/// Which lights of `lights` cast shadows in `cell`: the `shadowed` covering the most of the
/// screen.
fn pick(cell: ShadowCell, lights: &[SceneLight], camera: &FrameCamera, height: u32) -> Vec<bool> {
    let mut marked = lights.to_vec();
    if cell.mode != ShadowMode::None {
        pick_shadowed(&mut marked, camera, height as f32, cell.shadowed as usize);
    }
    marked.iter().map(|l| l.casts_shadow).collect()
}

/// Renders and measures one cell of the shadow axis.
pub fn measure_cell(
    gpu: &GpuContext,
    (name, scene): (&str, &Scene),
    setup: &Setup,
    lights: &MovingLights,
    cell: ShadowCell,
    config: RendererConfig,
    plan: FramePlan,
) -> Result<CellRecord> {
    let mut config = config;
    config.shadows.cache = cell.mode != ShadowMode::Uncached;
    let mut renderer = Renderer::new(gpu, config)?;
    renderer.prepare_scene(scene)?;
    let target = create_target(gpu.device(), &config);
    let camera = default_camera(scene, setup.width as f32 / setup.height as f32);
    let mover = moving_instance(scene).context("the scene has no instance to move")?;
    let start = scene.instances[mover].world_from_mesh;
    let mover = renderer.scene_instance(mover)?;
    renderer.set_instance_dynamic(mover, true)?;
    let casts = pick(cell, &lights.at(0), &camera, setup.height);
    let mut advance = |r: &mut Renderer, frame: u32| -> Result<()> {
        match cell.mode {
            ShadowMode::LightsMoving => {
                r.set_lights(&shadow_lights(cell, &lights.at(frame), &casts))?
            }
            _ if frame == 0 => r.set_lights(&shadow_lights(cell, &lights.at(0), &casts))?,
            _ => {}
        }
        if cell.mode == ShadowMode::Moving {
            let lift = 0.6 * (frame as f32 * 0.3).sin();
            r.set_instance_transform(mover, Mat4::from_translation(Vec3::Y * lift) * start)?;
        }
        Ok(())
    };
    let m = measure::measure(&mut renderer, &target, &camera, &mut advance, plan)?;
    renderer.finish();
    let count = casts.len() as u32;
    let mut record = CellRecord::empty(name, setup, count);
    record.fill(&m, &mut renderer);
    record.shadow_mode = cell.mode.name().into();
    record.shadow_kind = if cell.mode == ShadowMode::None {
        String::new()
    } else {
        cell.kind.name().into()
    };
    record.shadowed = cell.shadowed;
    record.shadow_median_ms = m.passes.get("shadow atlas").and_then(|s| s.median());
    record.shadow_p90_ms = m.passes.get("shadow atlas").and_then(|s| s.p90());
    record.shadow_cpu_median_ms = m.shadow_cpu_ms.median();
    if let Some(s) = &m.shadows {
        record.shadows_granted = s.shadowed;
        record.shadow_regions = s.regions.len() as u32;
        record.shadow_redrawn = s.cache.redrawn;
        record.shadow_copied = s.cache.copied;
        record.shadow_untouched = s.cache.untouched;
        record.shadow_draws = s.cache.draws;
        record.shadow_degraded = s.degraded.len() as u32;
        record.shadow_evicted = s.evicted.len() as u32;
    }
    Ok(record)
}

/// The baseline (no shadows) of `r`'s scene, size, MSAA, path and light count.
fn baseline<'a>(
    records: impl IntoIterator<Item = &'a CellRecord>,
    r: &CellRecord,
) -> Option<&'a CellRecord> {
    records.into_iter().find(|b| {
        b.shadow_mode == "none"
            && b.scene == r.scene
            && (b.width, b.height, b.msaa, b.tile, b.lights)
                == (r.width, r.height, r.msaa, r.tile, r.lights)
            && b.path == r.path
            && b.scalarize == r.scalarize
    })
}

/// The shadow section of `bench.md` (empty without shadow cells).
pub fn markdown(records: &[CellRecord]) -> String {
    let rows: Vec<&CellRecord> = records.iter().filter(|r| r.is_shadow_cell()).collect();
    if rows.is_empty() {
        return String::new();
    }
    let mut out = String::from(
        "\n### Shadows\n\nGPU ms per frame, median (p90); a frame that skips the shadow pass \
         counts 0. Shadow CPU = planning and uploads (median ms). Share = shadow pass ÷ all \
         passes. Added = whole-frame GPU median over the same frame without shadows (shadow \
         pass plus the lookups in forward shading). Regions and work are those of the last \
         timed frame; draws = the casts drawn into regions, counted on the GPU where it culls \
         them (the newest count that arrived by the last timed frame). CPU frame = the \
         renderer's CPU per frame (prepare + record + submit, median ms).\n\n| path | lights \
         | shadowed (got) | mode | regions | redrawn / copied / untouched | draws | degraded / \
         evicted | shadow GPU | shadow CPU | CPU frame | forward | total | share | added \
         |\n|---|---:|---|---|---:|---|---:|---|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in &rows {
        let shadowed = if r.shadow_mode == "none" {
            "–".into()
        } else {
            format!("{} {} ({})", r.shadowed, r.shadow_kind, r.shadows_granted)
        };
        // A cell whose frames all skipped the shadow pass has no samples of it: 0 ms.
        let shadow = r.shadow_median_ms.unwrap_or(0.0);
        let share = if r.gpu_total_median_ms > 0.0 && r.shadow_mode != "none" {
            format!("{:.1}%", 100.0 * shadow / r.gpu_total_median_ms)
        } else {
            "–".into()
        };
        let added = baseline(records, r)
            .filter(|b| r.shadow_mode != "none" && b.frames > 0)
            .map_or_else(
                || "–".into(),
                |b| format!("{:+.3}", r.gpu_total_median_ms - b.gpu_total_median_ms),
            );
        let _ = writeln!(
            out,
            "| {} {}×{} MSAA {} | {} | {shadowed} | {} | {} | {} / {} / {} | {} | {} / {} | {} ({}) | {} | {:.3} | {} | {:.3} | {share} | {added} |",
            r.label(),
            r.width,
            r.height,
            r.msaa,
            r.lights,
            r.shadow_mode,
            r.shadow_regions,
            r.shadow_redrawn,
            r.shadow_copied,
            r.shadow_untouched,
            r.shadow_draws,
            r.shadow_degraded,
            r.shadow_evicted,
            ms(Some(shadow)),
            ms(Some(r.shadow_p90_ms.unwrap_or(0.0))),
            ms(r.shadow_cpu_median_ms),
            r.cpu_frame_ms(),
            ms(r.forward_median_ms),
            r.gpu_total_median_ms,
        );
    }
    out += &goal(&rows);
    out
}

/// The goal and the anti-anchor, from the 64-point-light cells where there are some.
fn goal(rows: &[&CellRecord]) -> String {
    let find = |mode: &str| {
        rows.iter()
            .find(|r| r.shadowed == 64 && r.shadow_kind == "point" && r.shadow_mode == mode)
    };
    let Some(s) = find("static") else {
        return String::new();
    };
    let pass = s.shadow_median_ms.unwrap_or(0.0);
    let added = baseline(rows.iter().copied(), s)
        .map(|b| format!("{:+.3} ms", s.gpu_total_median_ms - b.gpu_total_median_ms))
        .unwrap_or_else(|| "–".into());
    let mut out = format!(
        "\n64 shadowed point lights, static frame: the shadow pass costs {pass:.3} ms GPU per \
         frame (goal ≤ 0.1 ms: {}); its CPU planning {} ms; the whole frame {added} against no \
         shadows (the lookups in forward shading).",
        if pass <= 0.1 { "met" } else { "missed" },
        ms(s.shadow_cpu_median_ms),
    );
    for mode in ["moving", "uncached"] {
        if let Some(r) = find(mode) {
            let _ = write!(
                out,
                " {mode}: {} ms GPU, {} regions redrawn, {} copied, {} draws.",
                ms(Some(r.shadow_median_ms.unwrap_or(0.0))),
                r.shadow_redrawn,
                r.shadow_copied,
                r.shadow_draws
            );
        }
    }
    out += " Anti-anchor: Bevy users report 9 shadowed point lights taking a scene from 160 to \
            22 FPS (6.3 → 45 ms per frame).\n";
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_zero_count_is_one_baseline_and_others_cross_kinds_and_modes() {
        let axes = ShadowAxes {
            counts: vec![0, 16, 64],
            kinds: vec![ShadowKind::Point, ShadowKind::Spot],
            modes: vec![ShadowMode::Static, ShadowMode::Uncached],
        };
        let all = cells(&axes);
        assert_eq!(all.len(), 1 + 2 * 2 * 2);
        assert_eq!(all[0].mode, ShadowMode::None);
        assert!(
            all[1..]
                .iter()
                .all(|c| c.shadowed > 0 && c.mode != ShadowMode::None)
        );
        assert!(
            cells(&ShadowAxes::default()).is_empty(),
            "no --shadowed, no shadow cells"
        );
    }

    #[test]
    fn bad_kinds_and_modes_say_what_to_use() {
        assert!(
            ShadowKind::parse("area")
                .unwrap_err()
                .to_string()
                .contains("point, spot")
        );
        assert!(
            ShadowMode::parse("cached")
                .unwrap_err()
                .to_string()
                .contains("uncached")
        );
        for m in ["static", "moving", "lights-moving", "uncached"] {
            assert_eq!(ShadowMode::parse(m).unwrap().name(), m);
        }
    }

    #[test]
    fn spot_cells_turn_only_the_casters_into_spot_lights() {
        let light = SceneLight {
            kind: LightKind::Point,
            position: Vec3::ZERO,
            direction: Vec3::NEG_Z,
            color: Vec3::ONE,
            intensity: 1.0,
            range: Some(2.0),
            casts_shadow: false,
        };
        let cell = ShadowCell {
            shadowed: 1,
            kind: ShadowKind::Spot,
            mode: ShadowMode::Static,
        };
        let lights = shadow_lights(cell, &[light, light], &[false, true]);
        assert_eq!(lights[0], light);
        assert!(lights[1].casts_shadow);
        assert!(matches!(lights[1].kind, LightKind::Spot { .. }));
        assert_eq!(lights[1].direction, Vec3::NEG_Y);
    }

    fn record(mode: &str, shadowed: u32, total: f64, shadow: Option<f64>) -> CellRecord {
        let setup = Setup {
            scene: 0,
            width: 64,
            height: 32,
            msaa: 1,
            path: super::super::matrix::PathChoice::parse("clustered").unwrap(),
            tile: 0,
            scalarize: false,
            brute_force: false,
        };
        let mut r = CellRecord::empty("demo", &setup, 256);
        r.frames = 10;
        r.shadow_mode = mode.into();
        r.shadow_kind = if mode == "none" { "" } else { "point" }.into();
        r.shadowed = shadowed;
        r.gpu_total_median_ms = total;
        r.shadow_median_ms = shadow;
        r
    }

    #[test]
    fn the_section_compares_with_the_baseline_and_states_the_goal() {
        let records = [
            record("none", 0, 1.0, None),
            record("static", 64, 1.25, Some(0.0)),
            record("uncached", 64, 3.0, Some(1.5)),
        ];
        let md = markdown(&records);
        assert!(md.contains("+0.250"), "{md}");
        assert!(md.contains("+2.000"), "{md}");
        assert!(md.contains("50.0%"), "{md}");
        assert!(md.contains("goal ≤ 0.1 ms: met"), "{md}");
        assert!(md.contains("+0.250 ms against no shadows"), "{md}");
        assert!(md.contains("160 to 22 FPS"), "{md}");
        assert!(markdown(&[]).is_empty());
    }
}
