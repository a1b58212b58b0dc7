//! Project automation, run as `cargo xtask <command>`.
//!
//! Each command lives in its own module. The two a newcomer needs are `demo` (the main job) and
//! `test` (everything CI checks); `info` describes the GPU adapters, and `check-invariants` enforces
//! the architecture rules of ARCHITECTURE.md.

mod atlas_labels;
mod bench;
mod bench_codegen;
mod bench_particle_lighting;
mod bench_particles;
mod demo;
mod fuzz;
mod fuzz_dsl;
mod info;
mod invariants;
mod render;
mod shaders;
mod shaders_doc;
mod system;
mod test;
mod view;
mod web;
mod workspace;

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
    /// The main job: render the demo scene (lit frame, light-count heatmap, frame graph) into
    /// target/demo/ and print a short summary; installs the software Vulkan driver if needed.
    Demo(demo::Args),
    /// Render one frame of a glTF scene with every renderer option.
    Render(render::Args),
    /// The renderer in a window: fly around (WASD, mouse), switch path, MSAA, tile size and
    /// heatmap, add or remove lights, with per-pass GPU timings on screen.
    View(view::Args),
    /// Run every check CI runs: formatting, clippy, architecture invariants, spirv-val over every
    /// shaders_gen variant, all tests.
    Test(test::Args),
    /// Print every GPU adapter with the capabilities this project uses.
    Info(info::Args),
    /// Write every variant of every shaders_gen module (WGSL, SPIR-V) and tabulate them.
    Shaders(shaders::Args),
    /// Generated differential test of DSL expressions and statement programs: GPU against the
    /// host interpreter, failures printed shrunk.
    FuzzDsl(fuzz_dsl::Args),
    /// Coverage-guided fuzzing of one target (gltf_load, dsl_codegen, frame_graph) with
    /// cargo-fuzz and libFuzzer; installs cargo-fuzz if needed.
    Fuzz(fuzz::Args),
    /// Check the architecture invariants of ARCHITECTURE.md.
    CheckInvariants,
    /// Every render path side by side over a matrix of lights, sizes, MSAA, tiles and
    /// scalarization: per-pass GPU time, CPU graph time, list bytes, cull efficiency, floors.
    Bench(bench::Args),
    /// Speed of the shader DSL's code generation: per variant, all of shaders_gen, the
    /// incremental rebuild after a one-line kernel change, and the output sizes.
    BenchCodegen(bench_codegen::Args),
    /// The web demo: build the renderer for the browser (wasm32, WebGPU) into target/web/ and
    /// serve the page on loopback; adds the wasm target if needed (the bindings are written by
    /// wasm-bindgen's own library).
    Web(web::Args),
    /// GPU time of the particle pipeline at full pools of 10k to 1M particles: simulation step,
    /// lighting-atlas layout and back-to-front sort.
    BenchParticles(bench_particles::Args),
}

fn main() -> anyhow::Result<()> {
    let cli = Cli::parse();
    system::private_runtime_dir()?;
    match cli.command {
        Command::Demo(args) => demo::run(&args),
        Command::Web(args) => web::run(&args),
        Command::Render(args) => render::run(&args, "target/render/frame.png"),
        Command::Test(args) => test::run(&args),
        Command::View(args) => view::run(&args),
        Command::Info(args) => info::run(&args),
        Command::Shaders(args) => shaders::run(&args),
        Command::Fuzz(args) => fuzz::run(&args),
        Command::FuzzDsl(args) => fuzz_dsl::run(&args),
        Command::CheckInvariants => invariants::run(),
        Command::Bench(args) => bench::run(&args),
        Command::BenchCodegen(args) => bench_codegen::run(&args),
        Command::BenchParticles(args) => bench_particles::run(&args),
    }
}
