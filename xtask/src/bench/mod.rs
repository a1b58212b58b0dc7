//! `cargo xtask bench`: every render path side by side, per pass, over a matrix of light counts,
//! sizes, MSAA counts, tile sizes and scalarization, with the culling pass set beside its
//! physical floor.
//!
//! Each cell renders warm-up frames, then timed frames back to back with moving lights, and
//! records per-pass GPU timestamps (median, p90), the CPU time of the frame graph, the light
//! list's bytes and, from one captured frame, the cull efficiency against the CPU reference. The
//! run writes `bench.csv` (one row per cell, written as it goes), `bench.md` and PNG charts.
//! `--report CSV` re-renders the Markdown and charts from a CSV, e.g. one from a GPU machine.
//!
//! `--shadowed 16,64,256` turns the run into the shadow benchmark: every set-up and light count
//! is measured with that many shadowed lights, per kind and per mode (static, one object moving,
//! every light moving, cache off), beside the same frame without shadows ([`shadows`]).
//!
//! `--decals 0,256,1024,4096` measures each cell of the light matrix again with that many
//! procedural decals, beside the same frame without ([`decals`]).
//!
//! Module map: [`sweep`] (the run: every cell, in this process or one per group), [`options`]
//! (scenes, axes and renderer set-ups from the arguments), [`matrix`] (axes → set-ups),
//! [`lights`] (the moving light set), [`shadows`] (the shadow axis), [`edits`] (editing the scene
//! by handle), [`measure`] (frames of one
//! cell), [`calibrate`] (ceilings and floors), [`record`] (the CSV row), [`reports`] (the run's
//! header and written reports), [`markdown`] and [`charts`] (reports).

pub mod calibrate;
pub(crate) mod charts;
pub(crate) mod decals;
mod edits;
mod lights;
mod markdown;
pub(crate) mod matrix;
mod measure;
mod options;
mod record;
mod reports;
mod scale;
mod shadows;
mod sweep;

pub use sweep::run;

use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Light counts (procedural point lights, plus the scene's own).
    #[arg(long, value_delimiter = ',', default_value = "1024,4096,16384,65536")]
    lights: Vec<u32>,
    /// Frame sizes, WxH.
    #[arg(long, value_delimiter = ',', default_value = "1920x1080,3840x2160")]
    sizes: Vec<String>,
    /// MSAA counts (those the adapter lacks are left out, and said so).
    #[arg(long, value_delimiter = ',', default_value = "1,2,4,8")]
    msaa: Vec<u32>,
    /// Paths: naive, naive-prez, tiled, 2.5d, clustered, tbdr, tbdr-per-sample, deferred,
    /// visibility, visibility-compute (the visibility path with the compute rasteriser).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "naive,naive-prez,tiled,2.5d,clustered"
    )]
    paths: Vec<String>,
    /// Tile sizes of the culled paths (tiled, 2.5D, and the clustered froxels' screen cells).
    #[arg(long, value_delimiter = ',', default_value = "8,16,32")]
    tiles: Vec<u32>,
    /// Culling levels: hierarchical (super-tiles, then tiles), brute-force (every tile tests
    /// every light), or both to compare.
    #[arg(long, value_delimiter = ',', default_value = "hierarchical")]
    cull: Vec<String>,
    /// Time each culling dispatch on its own (the `cull_depth/coarse/fine` columns); separate
    /// passes add to the culling total, so take totals from a run without it.
    #[arg(long)]
    cull_dispatch_times: bool,
    /// Scalarization: off, on (on needs SUBGROUP; left out without it).
    #[arg(long, value_delimiter = ',', default_value = "off,on")]
    scalarize: Vec<String>,
    /// Scenes measured after the built-in courtyard: glTF files, or `city:N` for a generated
    /// city of N instances.
    #[arg(long)]
    scene: Vec<PathBuf>,
    /// Leave the built-in courtyard out (only the --scene files).
    #[arg(long)]
    no_demo_scene: bool,
    /// Draw every draw of the scene, without GPU culling against the view (the baseline of the
    /// scene-size table).
    #[arg(long)]
    no_cull_draws: bool,
    /// Cull the scene's draws against the view frustum only, without two-phase occlusion
    /// culling.
    #[arg(long)]
    no_occlusion: bool,
    /// Tonemap with the full-screen fragment pass instead of the compute kernel and its copy
    /// (`RendererConfig::compute_tonemap`), to compare the two.
    #[arg(long)]
    fragment_tonemap: bool,
    /// Also rasterise the visibility path's opaque triangles in compute, beside its raster
    /// pass (`ComputeRasterPass`, adapters with 64-bit atomic min/max): the `compute_raster`
    /// column (`visibility-compute` has it in the frame already). The value is the pixel-box
    /// area up to which one invocation rasterises a triangle (0: every triangle by 16×16
    /// tiles). It adds its time to the frame's.
    #[arg(long)]
    compute_raster: Option<u32>,
    /// Timed frames per cell.
    #[arg(long, default_value_t = 30)]
    frames: u32,
    /// Untimed frames before them.
    #[arg(long, default_value_t = 2)]
    warmup: u32,
    /// Seconds of timed frames after which a cell stops early (its note says so); naive cells
    /// whose estimate exceeds twice this are skipped.
    #[arg(long, default_value_t = 1.2)]
    cell_budget: f64,
    /// Lights reaching a point of the light box on average (ranges shrink as counts grow).
    #[arg(long, default_value_t = 16.0)]
    light_density: f32,
    /// Seed of the lights.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Depth probes per captured frame for the cull efficiency.
    #[arg(long, default_value_t = 16_384)]
    probes: u32,
    /// Measure copy bandwidth and FMA rate first, for the floor column.
    #[arg(long)]
    calibrate: bool,
    /// Reduced sizes for software drivers (under 10 minutes on lavapipe): 256x144 and 384x216,
    /// lights 64, 256, 1024, 4096, 1 warm-up, 0.75 s of timed frames per cell.
    #[arg(long)]
    quick: bool,
    /// Run each scene × size × MSAA group in its own process, so memory a driver keeps per
    /// frame is returned between groups (lavapipe 22.3 keeps ~10 MB per frame in its queue
    /// thread). `--quick` turns it on.
    #[arg(long)]
    isolate: bool,
    /// Internal: run only this group (a child of `--isolate`).
    #[arg(long, hide = true)]
    group: Option<usize>,
    /// Internal: the parent's calibration, bytes/s and FLOP/s.
    #[arg(long, hide = true, value_delimiter = ',')]
    ceilings: Option<Vec<f64>>,
    /// Shadowed light counts: with it, the run is the shadow benchmark (each count of the
    /// procedural lights casts shadows, picked by screen influence; 0 adds the frame without
    /// shadows). Each count must be at most every --lights count.
    #[arg(long, value_delimiter = ',')]
    shadowed: Vec<u32>,
    /// What the shadowed lights are: point (six cube faces each), spot (pointing down).
    #[arg(long, value_delimiter = ',', default_value = "point,spot")]
    shadow_kinds: Vec<String>,
    /// What changes between frames: static (everything cached), moving (one dynamic object
    /// moves), lights-moving (every light moves), uncached (static, cache off).
    #[arg(long, value_delimiter = ',', default_value = "static,moving,uncached")]
    shadow_modes: Vec<String>,
    /// Decal counts: each cell of the light matrix with that many procedural decals on the
    /// scene's surfaces (0: none).
    #[arg(long, value_delimiter = ',', default_value = "0")]
    decals: Vec<u32>,
    /// Side of the shadow atlas in texels.
    #[arg(long, default_value_t = 8192)]
    shadow_atlas: u32,
    /// Output folder for bench.csv, bench.md and the charts.
    #[arg(long, default_value = "target/bench")]
    out: PathBuf,
    /// Only re-render bench.md and the charts from this CSV (no GPU needed).
    #[arg(long)]
    report: Option<PathBuf>,
    /// Adapter name substring (also RENDERER_ADAPTER).
    #[arg(long)]
    adapter: Option<String>,
}
