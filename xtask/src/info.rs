//! `cargo xtask info`: every adapter wgpu finds, with the capabilities this project uses.

use anyhow::Result;
use renderer::gpu::{self, AdapterReport, GpuOptions};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Mark the adapter whose name contains this (case-insensitive) as selected.
    #[arg(long)]
    adapter: Option<String>,
}

#[expect(clippy::print_stdout, reason = "a command-line report")]
pub fn run(args: &Args) -> Result<()> {
    let options = GpuOptions::from_env().with_adapter_name(args.adapter.clone());
    let adapters = pollster::block_on(gpu::enumerate_adapters(&options));
    if adapters.is_empty() {
        anyhow::bail!(renderer::GpuError::NoAdapter {
            backends: options.backends
        });
    }
    let wanted = options.adapter_name.as_deref().map(str::to_lowercase);
    let selected = adapters
        .iter()
        .position(|a| {
            wanted
                .as_deref()
                .is_none_or(|w| a.get_info().name.to_lowercase().contains(w))
        })
        .unwrap_or(usize::MAX);
    println!("{} adapter(s) on {:?}:", adapters.len(), options.backends);
    for (i, adapter) in adapters.iter().enumerate() {
        let mark = if i == selected { " [selected]" } else { "" };
        println!("\n#{i}{mark} {}", AdapterReport::new(adapter));
    }
    if selected == usize::MAX {
        println!("\nNo adapter name contains {:?}.", options.adapter_name);
    }
    Ok(())
}
