//! The viewer's command line: scene, lights, window size, path and MSAA, shader hot reload, and
//! the unattended-run options (frames, script, screenshots) its tests use.

use std::path::PathBuf;

use clap::Parser;

/// Command line of the viewer.
#[derive(Debug, Clone, Parser)]
#[command(
    name = "viewer",
    about = "The renderer in a window: fly around, switch paths, see GPU timings"
)]
pub struct Args {
    /// glTF scene (.gltf or .glb), or `city:N` for a generated city of N instances; without
    /// it, the built-in courtyard.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Procedural point lights.
    #[arg(long, default_value_t = 1024)]
    pub lights: usize,
    /// Procedural decals (scorch marks, stains, painted signs) on the scene's surfaces.
    #[arg(long, default_value_t = 96)]
    pub decals: usize,
    /// Particles of the built-in smoke, sparks and dust (about this many live at once); 0: none.
    #[arg(long, default_value_t = 20_000)]
    pub particles: u32,
    /// Seed of the procedural lights and decals.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Window size, WxH.
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    pub size: (u32, u32),
    /// naive | naive-prez | tiled | 2.5d | clustered.
    #[arg(long, default_value = "tiled")]
    pub path: renderer::frame::RenderPath,
    /// MSAA sample count (1 where the adapter lacks it).
    #[arg(long, default_value_t = 4)]
    pub msaa: u32,
    /// Quit after this many frames (with a fixed 1/60 s time step, for reproducible runs).
    #[arg(long)]
    pub frames: Option<u32>,
    /// Scripted key presses, `FRAME:KEY[ xN],..` (see the viewer's `script` module).
    #[arg(long, value_parser = viewer::script::parse_script)]
    pub script: Option<viewer::script::Script>,
    /// Write the last frame (before the overlay) to this PNG.
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// Take the screenshot with the overlay drawn.
    #[arg(long, requires = "screenshot")]
    pub screenshot_overlay: bool,
    /// Hot-reload the DSL shaders from this folder of `shaders_gen` sources; by default the
    /// workspace's `shaders_gen/src` when the viewer runs from its checkout.
    #[arg(long)]
    pub watch_shaders: Option<PathBuf>,
    /// Do not watch the shader sources.
    #[arg(long, conflicts_with = "watch_shaders")]
    pub no_watch: bool,
    /// After the first frame and after every hot reload, write `reload-N.png` and
    /// `reload-N-overlay.png` (with the overlay and its messages) to this folder.
    #[arg(long)]
    pub reload_shots: Option<PathBuf>,
    /// Quit once this many hot reloads (good or refused) have had their screenshots written.
    #[arg(long, requires = "reload_shots")]
    pub exit_after_reloads: Option<u32>,
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    s.split_once('x')
        .and_then(|(w, h)| Some((w.parse().ok()?, h.parse().ok()?)))
        .filter(|&(w, h): &(u32, u32)| (16..=8192).contains(&w) && (16..=8192).contains(&h))
        .ok_or_else(|| format!("{s:?}: use WxH with each side 16..=8192, e.g. 1280x720"))
}
