//! The run's header (adapter, driver, date, command, calibration, frame plan) and the reports
//! written from its records.

use std::path::Path;

use anyhow::{Context as _, Result};
use renderer::GpuContext;

use super::measure::FramePlan;
use super::record::CellRecord;
use super::{Args, calibrate, charts, markdown};

#[expect(clippy::print_stdout, reason = "command-line report")]
pub(super) fn write_markdown(meta: &str, records: &[CellRecord], out: &Path) -> Result<()> {
    let md = out.join("bench.md");
    std::fs::write(&md, markdown::report(meta, records))
        .with_context(|| format!("writing {}", md.display()))?;
    println!("wrote {}", md.display());
    Ok(())
}

#[expect(clippy::print_stdout, reason = "command-line report")]
pub(super) fn write_charts(records: &[CellRecord], out: &Path) -> Result<()> {
    for png in charts::write_charts(records, out)? {
        println!("wrote {}", png.display());
    }
    let matrix: Vec<CellRecord> = records
        .iter()
        .filter(|r| !r.is_shadow_cell())
        .cloned()
        .collect();
    if let Some(png) = charts::scale::write_scale_chart(&matrix, out)? {
        println!("wrote {}", png.display());
    }
    Ok(())
}

/// The run's header: adapter, driver, date, command, calibration, frame plan.
pub(super) fn meta(
    args: &Args,
    gpu: &GpuContext,
    ceilings: Option<calibrate::Ceilings>,
    left_out: &[String],
    plan: &FramePlan,
) -> String {
    let date = std::process::Command::new("date")
        .args(["-u", "+%Y-%m-%d %H:%M UTC"])
        .output()
        .ok()
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map_or_else(|| "unknown".into(), |s| s.trim().to_string());
    let command: Vec<String> = std::env::args().skip(1).collect();
    let mut s = format!(
        "## Run of {date}\n\n- Command: `cargo xtask {}`\n- Adapter: `{}`\n- Driver: `{} {}`\n\
         - Frames: {} warm-up, {} timed per cell (stopping early after {:.2} s, at least {}); \
         light density {} (lights reaching a point on average), seed {}\n",
        command.join(" "),
        gpu.report().name,
        gpu.report().driver,
        gpu.report().driver_info,
        plan.warmup,
        plan.frames,
        plan.budget.as_secs_f64(),
        plan.min_frames,
        args.light_density,
        args.seed
    );
    if let Some(c) = ceilings {
        s += &format!(
            "- Calibration: copy bandwidth {:.0} GB/s, FMA rate {:.2} TFLOP/s (floor = max(depth \
             bytes ÷ bandwidth, cells × lights × {} FLOP ÷ FMA rate))\n",
            c.bytes_per_s / 1e9,
            c.flop_per_s / 1e12,
            calibrate::FLOP_PER_SPHERE_TEST
        );
    }
    for l in left_out {
        s += &format!("- Left out: {l}\n");
    }
    s
}
