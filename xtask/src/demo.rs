//! `cargo xtask demo`: the main job. Renders a frame through the GPU context and writes a PNG.

use anyhow::{Context as _, Result};
use renderer::{GpuContext, GpuOptions, test_pattern};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Use the adapter whose name contains this (case-insensitive); also `RENDERER_ADAPTER`.
    #[arg(long)]
    adapter: Option<String>,
    /// Frame width and height in pixels.
    #[arg(long, default_value_t = 512)]
    size: u32,
    /// Output PNG; defaults to target/demo/frame.png.
    #[arg(long)]
    out: Option<std::path::PathBuf>,
}

#[expect(clippy::print_stdout, reason = "a command-line report")]
pub fn run(args: &Args) -> Result<()> {
    anyhow::ensure!(
        (1..=8192).contains(&args.size),
        "--size must be 1..=8192, got {}",
        args.size
    );
    let options = GpuOptions::from_env().with_adapter_name(args.adapter.clone());
    let gpu = GpuContext::new_blocking(&options)?;
    println!("adapter: {}", gpu.report);
    let frame = test_pattern::render(&gpu, args.size, args.size)?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| crate::workspace_root().join("target/demo/frame.png"));
    if let Some(dir) = out.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    image::save_buffer(
        &out,
        &frame.rgba,
        frame.width,
        frame.height,
        image::ExtendedColorType::Rgba8,
    )
    .with_context(|| format!("writing {}", out.display()))?;
    match frame.gpu_time {
        Some(t) => println!(
            "GPU time (test pattern pass): {:.3} ms",
            t.as_secs_f64() * 1e3
        ),
        None => println!("GPU time: unavailable (adapter has no TIMESTAMP_QUERY)"),
    }
    println!(
        "wrote {}x{} frame to {}",
        frame.width,
        frame.height,
        out.display()
    );
    Ok(())
}
