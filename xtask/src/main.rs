//! Project automation, run as `cargo xtask <command>`.
//!
//! Each command lives in its own module. The two a newcomer needs are `demo` (the main job) and
//! `test` (everything CI checks); `info` describes the GPU adapters, and `check-invariants` enforces
//! the architecture rules of ARCHITECTURE.md.

mod bench_cull;
mod demo;
mod info;
mod invariants;
mod render;
mod shaders;
mod system;
mod test;

use clap::{Parser, Subcommand};

#[derive(Debug, Parser)]
#[command(
    name = "cargo xtask",
    about = "Project automation for the renderer and shader DSL"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Render the demo frame to a PNG under target/ and print the adapter and GPU time.
    Demo(demo::Args),
    /// Render one frame of a glTF scene with every renderer option.
    Render(render::Args),
    /// Run every check CI runs: formatting, clippy, architecture invariants, all tests.
    Test(test::Args),
    /// Print every GPU adapter with the capabilities this project uses.
    Info(info::Args),
    /// Write every variant of every shaders_gen module (WGSL, SPIR-V) and tabulate them.
    Shaders(shaders::Args),
    /// Check the architecture invariants of ARCHITECTURE.md.
    CheckInvariants,
    /// GPU time of the light-culling kernels beside the physical floor.
    BenchCull(bench_cull::Args),
}

fn main() -> anyhow::Result<()> {
    match Cli::parse().command {
        Command::Demo(args) => demo::run(&args),
        Command::Render(args) => render::run(&args, "target/render/frame.png"),
        Command::Test(args) => test::run(&args),
        Command::Info(args) => info::run(&args),
        Command::Shaders(args) => shaders::run(&args),
        Command::CheckInvariants => invariants::run(),
        Command::BenchCull(args) => bench_cull::run(&args),
    }
}

/// The workspace root (the parent of this crate's manifest directory).
fn workspace_root() -> std::path::PathBuf {
    let manifest_dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    manifest_dir
        .parent()
        .map_or_else(|| manifest_dir.to_path_buf(), std::path::Path::to_path_buf)
}
