//! Compiles DSL source files with `codegen` and prints every variant's WGSL and timings.
//!
//! `cargo run --release -p codegen --example dump -- [--quiet] [--iters N] FILE..`

#![expect(
    clippy::print_stdout,
    reason = "a command-line tool that prints its report"
)]

use std::time::Instant;

fn main() {
    let mut quiet = false;
    let mut iters = 1;
    let mut files = vec![];
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--quiet" => quiet = true,
            "--iters" => iters = args.next().and_then(|n| n.parse().ok()).unwrap_or(1),
            _ => files.push(a),
        }
    }
    for f in files {
        let src = std::fs::read_to_string(&f).expect("readable file");
        let mut per_variant = vec![];
        let mut last = None;
        for _ in 0..iters {
            let t = Instant::now();
            match codegen::compile_source(&src) {
                Ok(c) => {
                    let n = c.keys.iter().filter(|k| !k.excluded).count();
                    per_variant.push(t.elapsed().as_secs_f64() * 1e3 / n as f64);
                    last = Some(c);
                }
                Err(e) => {
                    let start = e.span().start();
                    eprintln!("{f}:{}:{}: error: {e}", start.line, start.column);
                    std::process::exit(1);
                }
            }
        }
        let c = last.expect("at least one iteration");
        if !quiet {
            for v in &c.variants {
                println!("// ===== {} ({:?})", v.names.join(", "), v.gen_time);
                println!("{}", v.wgsl);
            }
        }
        let mut times: Vec<f64> = c
            .variants
            .iter()
            .map(|v| v.gen_time.as_secs_f64() * 1e3)
            .collect();
        times.sort_by(f64::total_cmp);
        println!(
            "{f}: per-variant generation (print + naga validate + SPIR-V + reflect): median {:.3} ms, max {:.3} ms",
            times[times.len() / 2],
            times[times.len() - 1]
        );
        per_variant.sort_by(f64::total_cmp);
        let median = per_variant[per_variant.len() / 2];
        let keys = c.keys.iter().filter(|k| !k.excluded).count();
        println!(
            "{f}: {keys} keys, {} distinct variants, median {median:.3} ms per key (whole pipeline, {iters} runs)",
            c.variants.len()
        );
    }
}
