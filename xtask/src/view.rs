//! `cargo xtask view`: the interactive viewer (the `viewer` crate), built in release mode, with
//! every argument passed on (`cargo xtask view -- --help` lists them). Installs the software
//! Vulkan driver first where no adapter exists, as `demo` does.

use anyhow::{Context as _, Result, bail};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Arguments of the viewer (`--scene`, `--lights`, `--size`, `--path`, `--msaa`, ..).
    #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
    viewer_args: Vec<String>,
}

pub fn run(args: &Args) -> Result<()> {
    crate::system::ensure_vulkan_adapter()?;
    let status = std::process::Command::new(env!("CARGO"))
        .args(["run", "--release", "-p", "viewer", "--"])
        .args(&args.viewer_args)
        .current_dir(crate::workspace::workspace_root())
        .status()
        .context("running cargo run -p viewer")?;
    if !status.success() {
        bail!("the viewer exited with {status}");
    }
    Ok(())
}
