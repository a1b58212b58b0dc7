//! `cargo xtask demo`: the main job. A preset of `cargo xtask render`: the committed glTF scene
//! with 1,024 procedural lights, 640×360, MSAA 4 (1 where unsupported), tiled Forward+.

use anyhow::Result;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Use the adapter whose name contains this (case-insensitive); also `RENDERER_ADAPTER`.
    #[arg(long)]
    adapter: Option<String>,
    /// Output PNG; defaults to target/demo/frame.png.
    #[arg(long)]
    out: Option<std::path::PathBuf>,
}

pub fn run(args: &Args) -> Result<()> {
    let render = crate::render::Args {
        scene: None,
        lights: 1024,
        seed: 1,
        light_radius: None,
        path: "tiled".into(),
        msaa: 4,
        size: "640x360".into(),
        tile: 16,
        scalarize: "auto".into(),
        camera: None,
        eye: None,
        target: None,
        view: "lit".into(),
        out: args.out.clone(),
        adapter: args.adapter.clone(),
    };
    crate::render::run(&render, "target/demo/frame.png")
}
