//! DSL source → the `codegen` library (parse, type-check, variant expansion, WGSL, naga
//! validation, SPIR-V, reflection), from grammar-aware generated programs.
//!
//! The fuzzer's bytes drive the choices of the differential tests' generators
//! (`tests::dsl_fuzz`: typed expressions and statement programs) through
//! [`Rng::from_bytes`], so most inputs are well-formed kernels. Around them it adds variant axes,
//! `requires(subgroup = ..)`, workgroup memory, atomics, barriers and subgroup operations, each
//! guarded as the DSL requires; then, for some inputs, breaks the program on purpose: a wrong
//! type, a subgroup operation outside its capability, a barrier in a fragment shader,
//! unsupported Rust syntax, a bad workgroup size or binding, an unknown name, a deleted token.
//!
//! The contract: no panic on any input; a well-formed program (no breakage) compiles; and every
//! error has a message and a span inside the source (the user's Rust span), never a bare
//! call-site span. Spans are checked by [`run`] (the regression replays and the generated test
//! below), not by the libFuzzer binary ([`run_fuzzing`]): proc-macro2 records no source
//! locations when built with `--cfg fuzzing`, as cargo-fuzz builds, so every span reads line 0
//! there.

use std::fmt::Write as _;

use ::tests::dsl_fuzz::generate::{GenConfig, Rng, expression, random_type};
use ::tests::dsl_fuzz::program::program;
use ::tests::dsl_fuzz::{run as expr_run, statements};

/// A generated source and whether it is meant to compile.
#[derive(Debug, Clone)]
pub struct Generated {
    pub source: String,
    /// False once a breakage was applied (it may still compile: a deleted token can be harmless).
    pub well_formed: bool,
}

/// Generates a program from `data` and compiles it. Panics only on a broken contract.
pub fn run(data: &[u8]) {
    check(&generate(&mut Rng::from_bytes(data)), true);
}

/// [`run`] without the span check, for the libFuzzer binary.
pub fn run_fuzzing(data: &[u8]) {
    check(&generate(&mut Rng::from_bytes(data)), false);
}

/// Compiles `g` and checks the contract (the spans too when `spans`).
pub fn check(g: &Generated, spans: bool) {
    let lines = g.source.lines().count();
    match codegen::compile_source(&g.source) {
        Ok(compiled) => {
            assert!(
                !compiled.variants.is_empty(),
                "a module compiled to no variant"
            );
        }
        Err(e) => {
            assert!(
                !g.well_formed,
                "a well-formed program failed to compile: {e}\n{}",
                g.source
            );
            for err in e {
                let message = err.to_string();
                assert!(!message.trim().is_empty(), "an error without a message");
                if !spans {
                    continue;
                }
                let start = err.span().start();
                assert!(
                    (1..=lines).contains(&start.line),
                    "error `{message}` points at line {} of a {lines}-line source:\n{}",
                    start.line,
                    g.source
                );
            }
        }
    }
}

/// The axes a generated module may declare.
const AXES: &[&str] = &[
    "",
    "axes(tile: u32 = [8, 16] => \"t\")",
    "axes(scalarize: bool = [false, true] => \"scalar\"), requires(subgroup = scalarize)",
    "axes(tile: u32 = [8, 16, 32] => \"t\", scalarize: bool = [false, true]), \
     exclude(tile == 32 && scalarize), requires(subgroup = scalarize)",
];

/// A program from the generators, with extras and perhaps breakages.
pub fn generate(rng: &mut Rng) -> Generated {
    let axes = AXES[rng.below(AXES.len())];
    let has_tile = axes.contains("tile");
    let has_scalarize = axes.contains("scalarize");
    let mut source = match rng.below(3) {
        0 => {
            let cfg = GenConfig {
                depth: 1 + rng.below(4) as u32,
                raw_shifts: rng.chance(20),
                floats: true,
            };
            let ty = random_type(rng);
            let (e, _) = expression(rng, ty, cfg);
            expr_run::kernel_source(&[&e])
        }
        1 => statements::kernel_source(&[&program(rng, 0)]),
        _ => statements::kernel_source(&[]),
    };
    let mut statics = String::new();
    let mut extra = String::new();
    if rng.chance(40) {
        let len = if has_tile { "tile * 8u32" } else { "64u32" };
        let _ = writeln!(
            statics,
            "    #[workgroup]\n    static SHARED: [u32; {len}];"
        );
        extra.push_str(
            "        SHARED[gid.x % 64u32] = gid.x;\n        workgroup_barrier();\n        \
             OUT[o] = SHARED[(gid.x + 1u32) % 64u32];\n",
        );
    }
    if rng.chance(30) {
        statics.push_str("    #[workgroup]\n    static COUNT: Atomic<u32>;\n");
        let op = [
            "fetch_add",
            "fetch_max",
            "fetch_min",
            "fetch_or",
            "fetch_xor",
        ][rng.below(5)];
        let _ = writeln!(extra, "        let previous = COUNT.{op}(gid.x);");
        extra.push_str("        OUT[o] = previous + COUNT.load();\n");
    }
    if has_scalarize && rng.chance(60) {
        let op = [
            "subgroup_add(gid.x)",
            "subgroup_exclusive_add(gid.x)",
            "subgroup_max(gid.x)",
            "subgroup_or(gid.x)",
            "subgroup_broadcast_first(gid.x)",
            "select(subgroup_all(gid.x > 3u32), 1u32, 0u32)",
        ][rng.below(6)];
        let _ = writeln!(
            extra,
            "        if scalarize {{\n            OUT[o] = {op};\n        }}"
        );
    }
    if rng.chance(20) {
        extra.push_str("        storage_barrier();\n");
    }
    source = source.replacen("#[shader]", &format!("#[shader({axes})]"), 1);
    source = source.replacen("mod fuzz {\n", &format!("mod fuzz {{\n{statics}"), 1);
    if let Some(end) = source.rfind("    }\n}") {
        source.insert_str(end, &extra);
    }
    let mut g = Generated {
        source,
        well_formed: true,
    };
    if rng.chance(50) {
        for _ in 0..1 + rng.below(3) {
            break_program(rng, &mut g);
        }
    }
    g
}

/// Replacements that make a program type-incorrect, capability-incorrect or unsupported.
const BREAKAGES: &[(&str, &str)] = &[
    ("u32", "f32"),
    ("u32", "u64"),
    ("UVec3", "Vec3"),
    ("i32", "usize"),
    ("as u32", "as String"),
    ("static OUT: [u32];", "static OUT: [UVec3];"),
    ("static OUT: [u32];", "static OUT: Vec<u32>;"),
    ("workgroup_size(64, 1, 1)", "workgroup_size(0, 1, 1)"),
    ("workgroup_size(64, 1, 1)", "workgroup_size(100000, 1, 1)"),
    ("workgroup_size(64, 1, 1)", "workgroup_size(tile, tile, 4)"),
    ("binding = 1", "binding = 0"),
    ("group = 0, binding = 1", "group = 9, binding = 1"),
    ("#[compute(workgroup_size(64, 1, 1))]", "#[fragment]"),
    ("#[compute(workgroup_size(64, 1, 1))]", "#[vertex]"),
    ("#[compute(workgroup_size(64, 1, 1))]", ""),
    ("global_invocation_id", "frag_depth"),
    ("global_invocation_id", "no_such_builtin"),
    ("if scalarize {", "{"),
    (
        "requires(subgroup = scalarize)",
        "requires(subgroup = tile == 8)",
    ),
    ("[false, true]", "[]"),
    ("=> \"t\"", "=> \"\""),
    ("tile == 32", "tile == 33"),
    ("COUNT.load()", "COUNT"),
    ("COUNT.", "OUT."),
    ("workgroup_barrier();", "workgroup_barrier(1u32);"),
    ("let ", "let mut &"),
    ("let ", "static "),
    ("OUT[o", "IN[o"),
    ("gid.x", "gid.w"),
    ("gid.x", "gid.xyz"),
    ("gid.x", "(gid.x, 1u32)"),
    ("gid.x", "|x| x"),
    ("gid.x", "match gid.x { _ => 0u32 }"),
    ("gid.x", "unsafe { gid.x }"),
    ("gid.x", "gid.x.no_such_method()"),
    ("gid.x", "\"text\""),
    ("gid.x", "println!(\"x\")"),
    ("gid.x", "1.5e40"),
    ("gid.x", "4294967296u32"),
    ("gid.x", "undefined_name"),
    ("    }\n}", "    }\n    fn main() {}\n}"),
    ("    }\n}", "    }\n    fn helper(x: &u32) -> u32 { *x }\n}"),
    ("    }\n}", "    }\n    fn helper() -> u32 { helper() }\n}"),
    (
        "    }\n}",
        "    }\n    struct S { a: Vec3, b: [Vec3; 2] }\n}",
    ),
    (
        "    }\n}",
        "    }\n    #[fragment]\n    fn fs() -> Vec4 { workgroup_barrier(); Vec4::ZERO }\n}",
    ),
    (
        "    }\n}",
        "    }\n    #[fragment]\n    fn fs() -> Vec4 { Vec4::splat(subgroup_add(1.0)) }\n}",
    ),
    ("mod fuzz {", "mod fuzz { use std::collections::HashMap;"),
    ("mod fuzz {", "mod fuzz { const N: u32 = N + 1u32;"),
    ("mod fuzz {", "mod fuzz { impl X {}"),
];

/// Applies one breakage: a replacement from [`BREAKAGES`] at one of its occurrences, or the
/// deletion or duplication of a random token.
fn break_program(rng: &mut Rng, g: &mut Generated) {
    let s = &mut g.source;
    if rng.chance(70) {
        let (from, to) = BREAKAGES[rng.below(BREAKAGES.len())];
        let hits: Vec<usize> = s.match_indices(from).map(|(i, _)| i).collect();
        if hits.is_empty() {
            return;
        }
        let at = hits[rng.below(hits.len().min(256))];
        s.replace_range(at..at + from.len(), to);
    } else {
        let tokens: Vec<(usize, &str)> = s
            .split_inclusive(|c: char| c.is_whitespace() || "(){}[];,.".contains(c))
            .scan(0, |pos, t| {
                let start = *pos;
                *pos += t.len();
                Some((start, t))
            })
            .collect();
        if tokens.is_empty() {
            return;
        }
        let (at, token) = tokens[rng.below(tokens.len())];
        let token = token.to_owned();
        if rng.chance(50) {
            s.replace_range(at..at + token.len(), "");
        } else {
            s.insert_str(at, &token);
        }
    }
    g.well_formed = false;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The contract, spans included, over generated programs: a few hundred inputs per
    /// `cargo test` (the fuzzer runs millions, without the span check).
    #[test]
    fn generated_programs_compile_or_fail_at_a_span_in_the_source() {
        let mut broken = 0;
        for seed in 0..300u64 {
            let g = generate(&mut Rng::new(seed));
            broken += usize::from(!g.well_formed);
            check(&g, true);
        }
        assert!(
            (90..=210).contains(&broken),
            "{broken} of 300 programs were broken"
        );
    }
}
