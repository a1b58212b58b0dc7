//! `viewer`: the renderer in a window, embedded as an engine embeds it. A winit window and a wgpu
//! surface; the renderer draws each frame into the swapchain texture through its public API
//! (`Renderer::render(camera, target)`), and an egui overlay shows per-pass GPU timings and the
//! settings. `cargo xtask view` runs it.
//!
//! Keys: WASD/QE fly, drag with the left mouse button to look, `1`-`8` path (naive, naive-prez,
//! tiled, 2.5D, clustered, tbdr, tbdr-per-sample, deferred), `F` the deferred paths' shading
//! frequency, `M` MSAA, `T` tile size, `H` heatmap, `C` decal heatmap, `V` shadow atlas, `P`
//! particle lighting (atlas or per pixel), `O` the particle lighting atlas, `G` GPU draw
//! culling, `+`/`-` double or halve the lights, Esc quits. `--frames N --script .. --screenshot FILE` run it unattended (tests).

mod app;
mod args;
mod overlay;

use anyhow::Result;
use clap::Parser;

fn main() -> Result<()> {
    let args = args::Args::parse();
    let event_loop = winit::event_loop::EventLoop::new()
        .map_err(|e| anyhow::anyhow!("cannot open a window: {e} (is a display available?)"))?;
    let mut app = app::App::new(args)?;
    event_loop.run_app(&mut app)?;
    app.finish()
}
