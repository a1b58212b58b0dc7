//! One measured cell of the benchmark matrix: its key, its figures, and its CSV row.
//!
//! The CSV is the benchmark's source of truth: the Markdown table and the charts are rendered
//! from it, so results carried back from a GPU machine can be re-reported anywhere
//! (`cargo xtask bench --report CSV`).

use std::path::Path;

use anyhow::{Context as _, Result};
use renderer::frame::Renderer;
use serde::{Deserialize, Serialize};

use super::matrix::Setup;
use super::measure::Measured;

/// One row of `bench.csv`: a cell of the matrix and what was measured for it. Times are GPU
/// timestamps in milliseconds (median and p90 over `frames` timed frames); a pass the path does
/// not run is empty.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct CellRecord {
    /// Scene name (file stem), `demo` for the built-in scene.
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub msaa: u32,
    /// `naive`, `naive-prez`, `tiled`, `2.5d`, `clustered`, `tbdr`, `tbdr-per-sample` or `deferred`.
    pub path: String,
    /// Tile size of the culled paths; 0 for the others.
    pub tile: u32,
    pub scalarize: bool,
    /// Culled without the super-tile level (every tile tests every light). Absent in CSVs
    /// written before the hierarchy existed, which were all brute force.
    #[serde(default = "brute_force_before_the_hierarchy")]
    pub brute_force: bool,
    /// Lights culled and shaded (procedural plus the scene's own punctual lights).
    pub lights: u32,
    /// Timed frames behind the medians (fewer than asked only when the cell's time budget ran
    /// out; `note` then says so).
    pub frames: u32,
    pub prez_median_ms: Option<f64>,
    pub prez_p90_ms: Option<f64>,
    pub cull_median_ms: Option<f64>,
    pub cull_p90_ms: Option<f64>,
    /// The culling pass's dispatches: per-tile depth, super-tile candidates, tile lists.
    #[serde(default)]
    pub cull_depth_median_ms: Option<f64>,
    #[serde(default)]
    pub cull_coarse_median_ms: Option<f64>,
    #[serde(default)]
    pub cull_fine_median_ms: Option<f64>,
    pub forward_median_ms: Option<f64>,
    pub forward_p90_ms: Option<f64>,
    pub tonemap_median_ms: Option<f64>,
    pub tonemap_p90_ms: Option<f64>,
    /// Median over frames of the sum of all passes.
    pub gpu_total_median_ms: f64,
    /// Median CPU time to build, compile and encode the frame graph.
    pub cpu_graph_median_ms: f64,
    /// Median CPU time to write the frame's uniforms and culling items (before the graph).
    pub cpu_upload_median_ms: f64,
    /// Median CPU time to finish and submit the frame's commands.
    #[serde(default)]
    pub cpu_submit_median_ms: f64,
    /// The scene's instances (nodes with a mesh) and triangles.
    #[serde(default)]
    pub instances: u64,
    #[serde(default)]
    pub triangles: u64,
    /// The scene's opaque and masked draws in the main view, and how many the last timed
    /// frame drew after GPU culling (empty with culling off).
    #[serde(default)]
    pub draws: u32,
    #[serde(default)]
    pub draws_visible: Option<u32>,
    /// Bytes of the light grid (`(offset, count)` per cell); 0 without culling.
    pub grid_bytes: u64,
    /// Bytes of the index list the frame filled (entries requested × 4).
    pub index_bytes_used: u64,
    /// Bytes allocated for the index list.
    pub index_bytes_allocated: u64,
    /// Lights listed ÷ lights that reach the sample, from the CPU reference on sampled pixels.
    pub cull_efficiency: Option<f64>,
    /// Mean number of lights reaching a probed surface sample (the light density as seen).
    pub lights_reaching_mean: Option<f64>,
    /// Physical floor of the culling pass in µs (needs `--calibrate`).
    pub cull_floor_us: Option<f64>,
    /// List entries dropped in the measured frames (0 means the image is exact).
    pub dropped: u32,
    pub note: String,
    /// Shadow axis (`--shadowed`): empty for a cell of the light matrix; otherwise `none` (no
    /// light casts a shadow: the baseline), `static` (nothing moves: everything cached),
    /// `moving` (one dynamic object moves every frame), `lights-moving` (every light moves every
    /// frame) or `uncached` (nothing moves, the cache is off: every region redrawn every frame).
    #[serde(default)]
    pub shadow_mode: String,
    /// `point` or `spot`: what the shadowed lights are (the others stay point lights).
    #[serde(default)]
    pub shadow_kind: String,
    /// Lights asked to cast shadows.
    #[serde(default)]
    pub shadowed: u32,
    /// Lights that got a shadow in the last timed frame (the atlas degrades, then evicts).
    #[serde(default)]
    pub shadows_granted: u32,
    /// Atlas regions (spot lights, cube faces) and their work in the last timed frame.
    #[serde(default)]
    pub shadow_regions: u32,
    #[serde(default)]
    pub shadow_redrawn: u32,
    #[serde(default)]
    pub shadow_copied: u32,
    #[serde(default)]
    pub shadow_untouched: u32,
    /// Caster draw calls of the last timed frame.
    #[serde(default)]
    pub shadow_draws: u32,
    /// Lights the full atlas degraded or evicted in the last timed frame.
    #[serde(default)]
    pub shadow_degraded: u32,
    #[serde(default)]
    pub shadow_evicted: u32,
    /// GPU ms of the shadow pass per frame (0 in frames that skipped it).
    #[serde(default)]
    pub shadow_median_ms: Option<f64>,
    #[serde(default)]
    pub shadow_p90_ms: Option<f64>,
    /// CPU ms of shadow planning per frame.
    #[serde(default)]
    pub shadow_cpu_median_ms: Option<f64>,
    /// Decal axis (`--decals`): procedural decals on the scene's surfaces (0: none).
    #[serde(default)]
    pub decals: u32,
    /// The deferred paths: the G-buffer pass (the visibility path: its raster pass), and the
    /// TBDR shading pass (traditional deferred's base pass; the visibility path's shading).
    #[serde(default)]
    pub gbuffer_median_ms: Option<f64>,
    #[serde(default)]
    pub deferred_median_ms: Option<f64>,
    /// Traditional deferred: the light volumes.
    #[serde(default)]
    pub volumes_median_ms: Option<f64>,
    /// The compute rasteriser beside the visibility raster (`--compute-raster`).
    #[serde(default)]
    pub compute_raster_median_ms: Option<f64>,
    /// Occlusion culling's second phase (`--no-occlusion` leaves it out): the late pre-Z (the
    /// late visibility raster on the visibility path), and the depth pyramid plus the late
    /// culling dispatch (the sum of their medians).
    #[serde(default)]
    pub prez_late_median_ms: Option<f64>,
    #[serde(default)]
    pub occlusion_median_ms: Option<f64>,
    /// The blended draws' order on the GPU (keys, sort, arguments), where the scene has any.
    #[serde(default)]
    pub blended_order_median_ms: Option<f64>,
    /// The deferred paths with MSAA: laying the overlay of blended surfaces and particles over
    /// the shaded image (the `overlay` pass; the forward pass draws into the overlay).
    #[serde(default)]
    pub overlay_median_ms: Option<f64>,
    /// Every timed pass's median GPU ms, `name=ms` separated by `;`, in name order: what the
    /// columns above leave out (scene culling, the shadow atlas, particles, ...).
    #[serde(default)]
    pub pass_medians: String,
    /// Editing the scene by handle (`bench::edits`, the first cell of each setup): CPU µs to
    /// add an instance (median and most), move one and remove one, and CPU ms of the frames
    /// that follow edits.
    #[serde(default)]
    pub edit_add_median_us: Option<f64>,
    #[serde(default)]
    pub edit_add_max_us: Option<f64>,
    #[serde(default)]
    pub edit_move_median_us: Option<f64>,
    #[serde(default)]
    pub edit_remove_median_us: Option<f64>,
    #[serde(default)]
    pub edit_frame_cpu_median_ms: Option<f64>,
    /// Streaming a mesh in and out (`bench::edits`): CPU µs to add a copy of a scene mesh
    /// (its vertices uploaded into free room) and to remove it again (median).
    #[serde(default)]
    pub edit_mesh_add_median_us: Option<f64>,
    #[serde(default)]
    pub edit_mesh_remove_median_us: Option<f64>,
}

impl CellRecord {
    /// The path label used in tables and chart legends, e.g. `tiled 16 scalar`.
    pub fn label(&self) -> String {
        let mut s = self.path.clone();
        if self.tile > 0 {
            s += &format!(" {}", self.tile);
        }
        if self.scalarize {
            s += " scalar";
        }
        if self.brute_force && self.tile > 0 {
            s += " brute";
        }
        s
    }

    /// The record of a cell before it is measured.
    pub fn empty(scene: &str, setup: &Setup, lights: u32) -> Self {
        Self {
            scene: scene.to_string(),
            width: setup.width,
            height: setup.height,
            msaa: setup.msaa,
            path: setup.path.name().to_string(),
            tile: setup.tile,
            scalarize: setup.scalarize,
            brute_force: setup.brute_force,
            lights,
            frames: 0,
            prez_median_ms: None,
            prez_p90_ms: None,
            cull_median_ms: None,
            cull_p90_ms: None,
            cull_depth_median_ms: None,
            cull_coarse_median_ms: None,
            cull_fine_median_ms: None,
            forward_median_ms: None,
            forward_p90_ms: None,
            tonemap_median_ms: None,
            tonemap_p90_ms: None,
            gpu_total_median_ms: 0.0,
            cpu_graph_median_ms: 0.0,
            cpu_upload_median_ms: 0.0,
            grid_bytes: 0,
            index_bytes_used: 0,
            index_bytes_allocated: 0,
            cull_efficiency: None,
            lights_reaching_mean: None,
            cull_floor_us: None,
            dropped: 0,
            note: String::new(),
            ..Default::default()
        }
    }

    /// Fills in what the timed frames of the cell measured.
    pub fn fill(&mut self, m: &Measured, renderer: &mut Renderer) {
        let record = self;
        let pass = |name: &str| m.passes.get(name);
        record.frames = m.frames;
        record.prez_median_ms = pass("pre-z").and_then(|s| s.median());
        record.prez_p90_ms = pass("pre-z").and_then(|s| s.p90());
        record.cull_median_ms = pass("light culling").and_then(|s| s.median());
        record.cull_p90_ms = pass("light culling").and_then(|s| s.p90());
        record.cull_depth_median_ms = pass("cull: tile depth").and_then(|s| s.median());
        record.cull_coarse_median_ms = pass("cull: super-tiles").and_then(|s| s.median());
        record.cull_fine_median_ms = pass("cull: tiles").and_then(|s| s.median());
        record.forward_median_ms = pass("forward").and_then(|s| s.median());
        record.forward_p90_ms = pass("forward").and_then(|s| s.p90());
        record.tonemap_median_ms = pass("tonemap").and_then(|s| s.median());
        record.tonemap_p90_ms = pass("tonemap").and_then(|s| s.p90());
        record.gbuffer_median_ms = pass("gbuffer")
            .or(pass("visibility"))
            .and_then(|s| s.median());
        record.prez_late_median_ms = pass("pre-z (late)")
            .or(pass("visibility (late)"))
            .and_then(|s| s.median());
        record.occlusion_median_ms = match (
            pass("depth pyramid").and_then(|s| s.median()),
            pass("scene culling (late)").and_then(|s| s.median()),
        ) {
            (Some(a), Some(b)) => Some(a + b),
            _ => None,
        };
        record.deferred_median_ms = pass("tbdr shading")
            .or(pass("deferred base"))
            .or(pass("visibility shading"))
            .and_then(|s| s.median());
        record.volumes_median_ms = pass("light volumes").and_then(|s| s.median());
        // Its triangles and its large triangles' tiles, two graph passes, for each half of
        // occlusion culling.
        record.compute_raster_median_ms = [
            "compute raster",
            renderer::extend::COMPUTE_RASTER_TILES_PASS,
            renderer::extend::COMPUTE_RASTER_LATE_PASS,
            renderer::extend::COMPUTE_RASTER_LATE_TILES_PASS,
        ]
        .into_iter()
        .filter_map(|name| pass(name).and_then(|s| s.median()))
        .reduce(|a, b| a + b);
        record.blended_order_median_ms = pass("blended order").and_then(|s| s.median());
        record.overlay_median_ms = pass("overlay").and_then(|s| s.median());
        record.pass_medians = m
            .passes
            .iter()
            .filter_map(|(name, s)| s.median().map(|ms| format!("{name}={ms:.4}")))
            .collect::<Vec<_>>()
            .join(";");
        record.gpu_total_median_ms = m.total.median().unwrap_or(0.0);
        record.cpu_graph_median_ms = m.cpu_graph_ms.median().unwrap_or(0.0);
        record.cpu_upload_median_ms = m.cpu_upload_ms.median().unwrap_or(0.0);
        record.cpu_submit_median_ms = m.cpu_submit_ms.median().unwrap_or(0.0);
        if let Some((grid, index)) = renderer.culler().lists().map(|l| l.bytes()) {
            record.grid_bytes = grid;
            record.index_bytes_allocated = index;
            record.index_bytes_used = (u64::from(m.requested_entries) * 4).min(index);
        }
        record.dropped = m.dropped;
        record.note.clone_from(&m.note);
        if let Some(d) = renderer.scene_draws() {
            record.draws = d.draws + d.blended;
            record.draws_visible = d.visible.map(|v| v + d.blended);
        }
    }

    /// The renderer's CPU per frame: prepare + record + submit, from the medians.
    pub fn cpu_frame_ms(&self) -> f64 {
        self.cpu_upload_median_ms + self.cpu_graph_median_ms + self.cpu_submit_median_ms
    }

    /// GPU time of the passes that draw the scene's geometry: pre-Z, and the G-buffer on the
    /// deferred paths or forward on the others.
    pub fn geometry_median_ms(&self) -> Option<f64> {
        let main = self.gbuffer_median_ms.or(self.forward_median_ms)?;
        let prez = self.prez_median_ms.unwrap_or(0.0) + self.prez_late_median_ms.unwrap_or(0.0);
        Some(prez + self.occlusion_median_ms.unwrap_or(0.0) + main)
    }

    /// Whether the cell belongs to the shadow axis (else to the light matrix).
    pub fn is_shadow_cell(&self) -> bool {
        !self.shadow_mode.is_empty()
    }

    /// Culling median over its floor, where both exist.
    pub fn cull_ratio_to_floor(&self) -> Option<f64> {
        Some(self.cull_median_ms? * 1e3 / self.cull_floor_us?)
    }
}

/// Milliseconds to three decimals for the reports, `–` when absent.
pub fn ms(v: Option<f64>) -> String {
    v.map_or_else(|| "–".into(), |v| format!("{v:.3}"))
}

fn brute_force_before_the_hierarchy() -> bool {
    true
}

/// Writes records to a CSV file, one row per cell, header first.
#[derive(Debug)]
pub struct CsvSink {
    writer: csv::Writer<std::fs::File>,
}

impl CsvSink {
    pub fn create(path: &Path) -> Result<Self> {
        Ok(Self {
            writer: csv::Writer::from_path(path)
                .with_context(|| format!("creating {}", path.display()))?,
        })
    }

    /// Appends one row and flushes, so an interrupted run keeps every finished cell.
    pub fn push(&mut self, record: &CellRecord) -> Result<()> {
        self.writer.serialize(record)?;
        self.writer.flush()?;
        Ok(())
    }
}

/// Reads every record of a CSV written by [`CsvSink`].
pub fn read_csv(path: &Path) -> Result<Vec<CellRecord>> {
    let mut reader =
        csv::Reader::from_path(path).with_context(|| format!("opening {}", path.display()))?;
    reader
        .deserialize()
        .map(|r| r.with_context(|| format!("reading {}", path.display())))
        .collect()
}
