//! The architecture invariants of ARCHITECTURE.md, checked rather than hoped for.
//!
//! Each check is a pure function over text (`cargo tree` output or source files), so the unit
//! tests below show that every check fails when its invariant is broken. The import-graph checks
//! (no circle between files, passes never import the frame orchestrator) parse the sources with
//! syn: the submodules build that graph, `import_tests` shows those checks failing.

mod api;
mod circles;
mod graph;
#[cfg(test)]
mod import_tests;
pub(crate) mod lengths;
mod modules;
mod resolve;
mod uses;

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context as _, Result, bail};

/// Crates that must never depend on wgpu: the DSL compiles shaders, it never runs them.
const WGPU_FREE_CRATES: &[&str] = &["shader-dsl", "codegen"];
/// The only direct dependencies `shader-dsl` may have: it is a syn -> codegen -> tokens adapter.
const SHADER_DSL_ALLOWED_DEPS: &[&str] = &["codegen", "proc-macro2", "quote", "syn"];
/// Lines of code (without comments and blank lines) `shader-dsl` may hold before it is no longer
/// a thin adapter; compiler logic belongs in `codegen`.
const SHADER_DSL_MAX_CODE_LINES: usize = 200;
/// Text that only hand-written shader code contains.
const SHADER_SOURCE_MARKERS: &[&str] = &[
    "@compute",
    "@vertex",
    "@fragment",
    "@group(",
    "@builtin(",
    "var<storage",
    "var<uniform",
    "var<workgroup",
    ".wgsl\"",
    ".spv\"",
    "create_shader_module_spirv",
    "create_shader_module_passthrough",
    "ShaderSource::SpirV",
    "ShaderSource::Glsl",
];
/// Text that only a bind group assembled by hand contains: `renderer` builds every bind group
/// through the DSL's generated builders (`shader_bind`), which number bindings from the
/// reflection.
const HAND_BOUND_MARKERS: &[&str] = &["create_bind_group(", "BindGroupEntry {"];
/// What production code of `renderer` may not name: the CPU culling reference, which must stay
/// independent of what it checks.
const REFERENCE_MARKERS: &[&str] = &["culling::reference", "super::reference"];
/// Files that may: the reference itself (compiled for tests and the `internals` feature only).
const REFERENCE_USERS: &[&str] = &["culling/reference/"];
/// Calls that begin a compute or render pass on a raw command encoder.
const PASS_BEGIN_MARKERS: &[&str] = &["begin_compute_pass(", "begin_render_pass("];
/// The files that may: the pass encoder itself, and the test pattern (recorded outside any
/// frame graph, with its own pass-level timestamps).
const PASS_BEGINNERS: &[&str] = &["graph/encoder.rs", "demo/test_pattern.rs"];
/// Files that may not use anything of the frame orchestrator: passes add themselves to a graph
/// the frame builds, they never reach back into it.
const PASSES_DIR: &str = "renderer/src/passes/";
const FRAME_DIR: &str = "renderer/src/frame/";

/// A broken invariant, named as in ARCHITECTURE.md.
#[derive(Debug, PartialEq, Eq)]
pub struct Violation {
    pub invariant: &'static str,
    pub detail: String,
}

#[expect(clippy::print_stdout, reason = "command-line report")]
pub fn run() -> Result<()> {
    let root = crate::workspace::workspace_root();
    let mut violations = Vec::new();
    for krate in WGPU_FREE_CRATES {
        let tree = cargo_tree(&root, &[krate, "-e", "normal,build"])?;
        violations.extend(check_no_wgpu(krate, &tree));
    }
    let direct = cargo_tree(&root, &["shader-dsl", "-e", "normal", "--depth", "1"])?;
    violations.extend(check_shader_dsl_deps(&direct));
    violations.extend(check_shader_dsl_is_thin(&read_rust_sources(
        &root.join("shader-dsl/src"),
    )?));
    let renderer_sources = read_rust_sources(&root.join("renderer/src"))?;
    violations.extend(check_no_shader_source(&renderer_sources));
    violations.extend(check_no_hand_bound_groups(&renderer_sources));
    violations.extend(check_passes_begin_through_the_pass_encoder(
        &renderer_sources,
    ));
    violations.extend(check_rendering_does_not_use_the_reference(
        &renderer_sources,
    ));
    violations.extend(
        api::messages_naming_flags(&renderer_sources)
            .into_iter()
            .map(|detail| Violation {
                invariant: "renderer messages name API items, not command-line flags",
                detail,
            }),
    );
    let mut manifests = Vec::new();
    for path in api::EMBEDDER_MANIFESTS {
        let text =
            std::fs::read_to_string(root.join(path)).with_context(|| format!("reading {path}"))?;
        manifests.push(((*path).to_owned(), text));
    }
    violations.extend(
        api::embedders_using_internals(&manifests)
            .into_iter()
            .map(|detail| Violation {
                invariant: "engines see the renderer's public API only",
                detail,
            }),
    );
    let workspace = read_workspace_sources(&root)?;
    violations.extend(check_no_import_circles(&workspace));
    violations.extend(check_passes_do_not_import_frame(&workspace));
    violations.extend(
        lengths::long_files(&read_crate_files(&root)?)
            .into_iter()
            .map(|(path, lines)| Violation {
                invariant: "no hand-written source file over 500 lines",
                detail: format!(
                    "{path} has {lines} lines: split it along a seam (tests in their own file)"
                ),
            }),
    );
    if violations.is_empty() {
        println!("architecture invariants hold");
        return Ok(());
    }
    for v in &violations {
        println!(
            "Architecture invariant broken: {}\n  {}",
            v.invariant, v.detail
        );
    }
    bail!("{} architecture invariant(s) broken", violations.len())
}

/// Package names (without versions) of `cargo tree -p <package> <args>`, one per line.
fn cargo_tree(root: &Path, args: &[&str]) -> Result<String> {
    let (package, rest) = args.split_first().context("cargo tree needs a package")?;
    let output = Command::new(env!("CARGO"))
        .args([
            "tree", "--quiet", "--prefix", "none", "--format", "{p}", "-p",
        ])
        .arg(package)
        .args(rest)
        .current_dir(root)
        .output()
        .context("running cargo tree")?;
    if !output.status.success() {
        bail!(
            "cargo tree -p {package} failed: {}",
            String::from_utf8_lossy(&output.stderr)
        );
    }
    Ok(String::from_utf8_lossy(&output.stdout).into_owned())
}

fn package_names(tree: &str) -> impl Iterator<Item = &str> {
    tree.lines().filter_map(|l| l.split_whitespace().next())
}

/// "`shader-dsl` and `codegen` do not depend on wgpu."
pub fn check_no_wgpu(krate: &str, tree: &str) -> Option<Violation> {
    let offenders: Vec<&str> = package_names(tree)
        .filter(|name| *name == "wgpu" || name.starts_with("wgpu-"))
        .collect();
    (!offenders.is_empty()).then(|| Violation {
        invariant: "shader-dsl and codegen do not depend on wgpu",
        detail: format!("{krate} depends on {}", dedup(offenders).join(", ")),
    })
}

/// "`shader-dsl` is only a syn -> codegen -> tokens adapter": its direct dependencies.
pub fn check_shader_dsl_deps(direct_tree: &str) -> Option<Violation> {
    let extra: Vec<&str> = package_names(direct_tree)
        .skip(1) // the first line is shader-dsl itself
        .filter(|name| !SHADER_DSL_ALLOWED_DEPS.contains(name))
        .collect();
    (!extra.is_empty()).then(|| Violation {
        invariant: "shader-dsl is only a syn -> codegen -> tokens adapter",
        detail: format!(
            "shader-dsl depends directly on {} (allowed: {})",
            dedup(extra).join(", "),
            SHADER_DSL_ALLOWED_DEPS.join(", ")
        ),
    })
}

/// "`shader-dsl` is only a syn -> codegen -> tokens adapter": its size.
pub fn check_shader_dsl_is_thin(sources: &[(String, String)]) -> Option<Violation> {
    let code_lines = sources
        .iter()
        .flat_map(|(_, text)| text.lines())
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with("//"))
        .count();
    (code_lines > SHADER_DSL_MAX_CODE_LINES).then(|| Violation {
        invariant: "shader-dsl is only a syn -> codegen -> tokens adapter",
        detail: format!(
            "shader-dsl holds {code_lines} lines of code (limit {SHADER_DSL_MAX_CODE_LINES}); \
             move compiler logic into codegen"
        ),
    })
}

/// "`renderer` contains no hand-written shader source: its GPU code comes from `shaders_gen`."
pub fn check_no_shader_source(sources: &[(String, String)]) -> Vec<Violation> {
    lines_with_markers(
        sources,
        SHADER_SOURCE_MARKERS,
        "renderer contains no hand-written shader source",
        "looks like shader code; write it in the DSL in shaders_gen",
    )
}

/// "`renderer` numbers no binding by hand: every bind group comes from a generated builder."
pub fn check_no_hand_bound_groups(sources: &[(String, String)]) -> Vec<Violation> {
    lines_with_markers(
        sources,
        HAND_BOUND_MARKERS,
        "renderer numbers no binding by hand",
        "builds a bind group by hand; use the module's generated `Group<N>` builder (or \
         `shader_bind::Resources`)",
    )
}

/// "Rendering does not use the CPU culling reference": outside the reference and the frame
/// capture, `renderer` names only `culling`'s own types (`culling::vocabulary`).
pub fn check_rendering_does_not_use_the_reference(sources: &[(String, String)]) -> Vec<Violation> {
    let production: Vec<(String, String)> = sources
        .iter()
        .filter(|(path, _)| !REFERENCE_USERS.iter().any(|r| path.contains(r)))
        .cloned()
        .collect();
    lines_with_markers(
        &production,
        REFERENCE_MARKERS,
        "rendering does not use the CPU culling reference",
        "names the CPU reference from production code; use the types of `crate::culling` \
         (`culling::vocabulary`)",
    )
}

/// "Every compute and render pass begins through the pass encoder": outside `graph/encoder.rs`
/// (and the standalone test pattern, which times itself), `renderer` begins passes with
/// `PassEncoder::begin_compute`/`begin_render`, so a device that can time only whole passes
/// (WebGPU) still times every graph pass.
pub fn check_passes_begin_through_the_pass_encoder(sources: &[(String, String)]) -> Vec<Violation> {
    let others: Vec<(String, String)> = sources
        .iter()
        .filter(|(path, _)| !PASS_BEGINNERS.iter().any(|b| path.ends_with(b)))
        .cloned()
        .collect();
    lines_with_markers(
        &others,
        PASS_BEGIN_MARKERS,
        "every compute and render pass begins through the pass encoder",
        "begins a pass outside the pass encoder, so browsers cannot time it; use \
         `PassEncoder::begin_compute` or `PassEncoder::begin_render` (`ctx.encoder`)",
    )
}

/// One violation of `invariant` per line of `sources` that contains one of `markers`:
/// `path:line: `marker` advice`.
fn lines_with_markers(
    sources: &[(String, String)],
    markers: &'static [&'static str],
    invariant: &'static str,
    advice: &'static str,
) -> Vec<Violation> {
    sources
        .iter()
        .flat_map(|(path, text)| {
            text.lines().enumerate().filter_map(move |(i, line)| {
                let marker = markers.iter().find(|m| line.contains(**m))?;
                Some(Violation {
                    invariant,
                    detail: format!("{path}:{}: `{marker}` {advice}", i + 1),
                })
            })
        })
        .collect()
}

/// "No circle between files": no two files of a crate use items defined in each other, directly or
/// around a ring. One violation per strongly connected component of the file graph.
pub fn check_no_import_circles(sources: &[(String, String)]) -> Vec<Violation> {
    const INVARIANT: &str = "no import circle between files";
    let graph = match graph::FileGraph::new(sources) {
        Ok(graph) => graph,
        Err(e) => return vec![unparsable(INVARIANT, e)],
    };
    circles::circles(&graph)
        .into_iter()
        .map(|c| Violation {
            invariant: INVARIANT,
            detail: format!(
                "{} files import each other: {}\n    edges: {}",
                c.files.len(),
                c.cycle,
                c.examples.join("\n           ")
            ),
        })
        .collect()
}

/// "Passes never import the frame orchestrator": no path in `renderer/src/passes/` names an item
/// defined in, or reached through, `renderer/src/frame/`.
pub fn check_passes_do_not_import_frame(sources: &[(String, String)]) -> Vec<Violation> {
    const INVARIANT: &str = "passes never import the frame orchestrator";
    let graph = match graph::FileGraph::new(sources) {
        Ok(graph) => graph,
        Err(e) => return vec![unparsable(INVARIANT, e)],
    };
    graph
        .uses_into(PASSES_DIR, FRAME_DIR)
        .into_iter()
        .map(|(file, uses)| Violation {
            invariant: INVARIANT,
            detail: format!(
                "{file} uses the frame orchestrator ({}); give the pass what it needs as \
                 arguments, or move the shared type below both",
                uses.join(", ")
            ),
        })
        .collect()
}

fn unparsable(invariant: &'static str, error: String) -> Violation {
    Violation {
        invariant,
        detail: format!("cannot parse {error}"),
    }
}

/// The `src/` files of every workspace member (a directory with a Cargo.toml and a `src/`), as
/// (path relative to the workspace root with `/` separators, contents).
fn read_workspace_sources(root: &Path) -> Result<Vec<(String, String)>> {
    read_relative(root, crate_source_files(root, &["src"])?)
}

/// Every hand-written `.rs` file of every crate of the workspace (its
/// [`lengths::SOURCE_FOLDERS`]), as (workspace-relative path, contents).
fn read_crate_files(root: &Path) -> Result<Vec<(String, String)>> {
    read_relative(root, crate_source_files(root, lengths::SOURCE_FOLDERS)?)
}

/// The `.rs` files of every crate directly under `parent` (a folder with a `Cargo.toml`), from
/// the folders of each crate that `folders` names, sorted.
pub(crate) fn crate_source_files(parent: &Path, folders: &[&str]) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for entry in
        std::fs::read_dir(parent).with_context(|| format!("reading {}", parent.display()))?
    {
        let dir = entry?.path();
        if !dir.join("Cargo.toml").is_file() {
            continue;
        }
        for folder in folders {
            if dir.join(folder).is_dir() {
                files.extend(crate::shaders::rust_files(&dir.join(folder))?);
            }
        }
    }
    files.sort();
    Ok(files)
}

/// `files` read, as (path relative to `root` with `/` separators, contents).
fn read_relative(root: &Path, files: Vec<PathBuf>) -> Result<Vec<(String, String)>> {
    let mut out = Vec::new();
    for path in files {
        let text = std::fs::read_to_string(&path)
            .with_context(|| format!("reading {}", path.display()))?;
        let relative = path.strip_prefix(root).unwrap_or(&path);
        let parts: Vec<_> = relative.iter().map(|p| p.to_string_lossy()).collect();
        out.push((parts.join("/"), text));
    }
    Ok(out)
}

/// Every `.rs` file under `dir`, as (path, contents), in a stable order.
fn read_rust_sources(dir: &Path) -> Result<Vec<(String, String)>> {
    let mut out = Vec::new();
    for path in crate::shaders::rust_files(dir)? {
        let text = std::fs::read_to_string(&path)
            .with_context(|| format!("reading {}", path.display()))?;
        out.push((path.display().to_string(), text));
    }
    Ok(out)
}

fn dedup(mut names: Vec<&str>) -> Vec<&str> {
    names.sort_unstable();
    names.dedup();
    names
}

#[cfg(test)]
mod tests;
