//! `bench-codegen`'s report as Markdown: the machine and build, the time per variant against the
//! target, the per-module table, output sizes, and the incremental rebuilds of the copy.

use std::fmt::Write as _;

use super::figures::{Report, Stats, TARGET_MS_PER_VARIANT};
use super::rebuild::EDITED_FILE;

/// The report as Markdown.
pub(super) fn markdown(r: &Report) -> String {
    let mut s = String::new();
    // Writing to a String cannot fail.
    let _ = write_markdown(&mut s, r);
    s
}

fn write_markdown(s: &mut String, r: &Report) -> std::fmt::Result {
    let build = if r.debug {
        "debug (dev profile; codegen and naga at opt-level 3)"
    } else {
        "release"
    };
    writeln!(s, "# Code generation benchmark\n")?;
    writeln!(
        s,
        "- Machine: {} CPU(s){}",
        r.cpus,
        r.cpu_model
            .as_deref()
            .map(|m| format!(", {m}"))
            .unwrap_or_default()
    )?;
    writeln!(s, "- xtask build (in-process compiler): {build}")?;
    if r.debug {
        writeln!(
            s,
            "- Note: this dev build of xtask leaves syn, proc-macro2 and quote unoptimised, while \
             the proc-macro gets them at opt-level 3 (`[profile.dev.build-override]`), so the \
             shared and emit times overstate the macro's"
        )?;
    }
    if let Some(v) = &r.rustc {
        writeln!(s, "- Toolchain: {v}")?;
    }
    let load = |l: Option<f64>| l.map_or_else(|| "?".to_owned(), |l| format!("{l:.2}"));
    writeln!(
        s,
        "- Load average (1 min) before / after: {} / {} (other work on the machine skews the \
         timings)",
        load(r.load.0),
        load(r.load.1)
    )?;
    writeln!(
        s,
        "- In-process: {} module(s), {} variant(s) ({} key(s)); 1 untimed warm-up run, then {} \
         timed run(s)\n",
        r.modules.len(),
        r.variants(),
        r.modules.iter().map(|m| m.keys).sum::<usize>(),
        r.iters
    )?;

    writeln!(s, "## Time per variant\n")?;
    writeln!(s, "| what | samples | median ms | p90 ms | max ms |")?;
    writeln!(s, "|---|---:|---:|---:|---:|")?;
    for (what, st) in [
        (
            "front end + variants + WGSL + naga + SPIR-V (shared part spread over the module's variants)",
            r.per_variant,
        ),
        (
            "WGSL + naga + SPIR-V + reflect only (`gen_time`, as `cargo xtask shaders`)",
            r.per_variant_stages,
        ),
    ] {
        writeln!(
            s,
            "| {what} | {} | {:.3} | {:.3} | {:.3} |",
            st.samples, st.median, st.p90, st.max
        )?;
    }
    let verdict = |v: f64| {
        if v <= TARGET_MS_PER_VARIANT {
            "met"
        } else {
            "NOT met"
        }
    };
    writeln!(
        s,
        "\nTarget ≤ {TARGET_MS_PER_VARIANT} ms per variant: median {}, p90 {}, max {}.\n",
        verdict(r.per_variant.median),
        verdict(r.per_variant.p90),
        verdict(r.per_variant.max)
    )?;

    writeln!(s, "## Per module (times: median over the timed runs)\n")?;
    writeln!(
        s,
        "| module | file | keys | variants | compile ms | of which shared ms | emit ms | WGSL bytes | SPIR-V bytes | largest variant (WGSL / SPIR-V bytes) |"
    )?;
    writeln!(s, "|---|---|---:|---:|---:|---:|---:|---:|---:|---|")?;
    for m in &r.modules {
        writeln!(
            s,
            "| {} | {} | {} | {} | {:.2} | {:.2} | {:.2} | {} | {} | {} ({} / {}) |",
            m.name,
            m.file,
            m.keys,
            m.variants,
            m.compile_ms,
            m.shared_ms,
            m.emit_ms,
            m.wgsl_bytes,
            m.spirv_bytes,
            m.largest.0,
            m.largest.1,
            m.largest.2
        )?;
    }
    let largest = r
        .modules
        .iter()
        .max_by_key(|m| m.largest.2)
        .map(|m| {
            format!(
                "{}::{} ({} / {})",
                m.name, m.largest.0, m.largest.1, m.largest.2
            )
        })
        .unwrap_or_default();
    writeln!(
        s,
        "| **total** | | {} | {} | {:.2} | | {:.2} | {} | {} | {largest} |\n",
        r.modules.iter().map(|m| m.keys).sum::<usize>(),
        r.variants(),
        r.total_compile_ms,
        r.total_expand_ms - r.total_compile_ms,
        r.modules.iter().map(|m| m.wgsl_bytes).sum::<usize>(),
        r.modules.iter().map(|m| m.spirv_bytes).sum::<usize>(),
    )?;
    writeln!(
        s,
        "Wall time for every variant of shaders_gen, in-process (median of the runs' totals): \
         compile {:.1} ms, compile + emit {:.1} ms; the untimed first (cold) run: compile + emit \
         {:.1} ms.\n",
        r.total_compile_ms, r.total_expand_ms, r.cold_expand_ms
    )?;

    writeln!(s, "## Incremental rebuild of shaders_gen\n")?;
    match &r.rebuild {
        None => writeln!(s, "Skipped (`--no-rebuild`).")?,
        Some(b) => {
            let flag = if b.release { " --release" } else { "" };
            writeln!(
                s,
                "`cargo build -p shaders_gen{flag}`, environment inherited; untimed warm-up build \
                 {:.2} s.\n",
                b.warmup_s
            )?;
            if b.release {
                writeln!(
                    s,
                    "In release, Cargo builds the proc-macro and its dependencies (codegen, naga) \
                     at opt-level 0 unless `[profile.release.build-override]` says otherwise.\n"
                )?;
            }
            writeln!(s, "| change | builds | median s | min s | max s | each s |")?;
            writeln!(s, "|---|---:|---:|---:|---:|---|")?;
            for (what, times) in [
                (
                    format!("one-line kernel edit in a copy of `{EDITED_FILE}`"),
                    &b.edit_s,
                ),
                ("touch, no token change".to_owned(), &b.touch_s),
            ] {
                let st = Stats::of(times);
                let min = times.iter().copied().fold(f64::INFINITY, f64::min);
                let each: Vec<String> = times.iter().map(|t| format!("{t:.2}")).collect();
                writeln!(
                    s,
                    "| {what} | {} | {:.2} | {min:.2} | {:.2} | {} |",
                    st.samples,
                    st.median,
                    st.max,
                    each.join(", ")
                )?;
            }
        }
    }
    Ok(())
}
