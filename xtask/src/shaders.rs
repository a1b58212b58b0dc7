//! `cargo xtask shaders`: every variant of every DSL module in `shaders_gen`, written out and
//! tabulated.
//!
//! It runs the DSL compiler (`codegen`) on the `shaders_gen` sources, exactly as the proc-macro
//! does, and times each variant. Outputs go to `target/shaders/<module>/<variant>.{wgsl,spv}`,
//! plus `.spvasm` from `spirv-dis` when installed. `--check` fails when `spirv-val` rejects any
//! variant (or is missing). `#[library]` modules are compiled on their own too (rows marked
//! `(library)`), and the modules that use them with their `uses(..)` resolved by name.
//! `--doc` also writes a Markdown page per module (`shaders_doc`).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use anyhow::{Context as _, Result, bail};
use codegen::rt::BindingKind;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Output folder; defaults to target/shaders.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Fail when spirv-val rejects any variant (or is not installed).
    #[arg(long)]
    check: bool,
    /// Only modules whose name contains this.
    #[arg(long)]
    module: Option<String>,
    /// Also write a Markdown page per module (variant table, bindings, host structs with their
    /// offsets) to `<out>/doc/`, with an index.
    #[arg(long)]
    doc: bool,
}

/// One row of the table.
struct Row {
    module: String,
    names: Vec<String>,
    wgsl_bytes: usize,
    spirv_words: usize,
    workgroup: String,
    bindings: String,
    features: &'static str,
    spirv_val: SpirvVal,
    gen_time: Duration,
}

#[derive(Debug, Clone, PartialEq, Eq)]
enum SpirvVal {
    Passed,
    Failed(String),
    NotInstalled,
}

impl Args {
    /// What `cargo xtask test` runs: every variant written to target/shaders and checked by
    /// `spirv-val`.
    pub fn check_all() -> Self {
        Self {
            out: None,
            check: true,
            module: None,
            doc: false,
        }
    }
}

#[expect(clippy::print_stdout, reason = "command-line report")]
pub fn run(args: &Args) -> Result<()> {
    let root = crate::workspace::workspace_root();
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| root.join("target/shaders"));
    let have_val = tool_available("spirv-val");
    let have_dis = tool_available("spirv-dis");
    let mut rows = Vec::new();
    let sources = dsl_modules(&root.join("shaders_gen/src"))?;
    check_all_modules_found(&sources)?;
    let libraries = dsl_libraries(&root.join("shaders_gen/src"))?;
    // Libraries first, each on its own (every function kept), then the shader modules with the
    // libraries their `uses(..)` names.
    let library_units = libraries
        .iter()
        .map(|(file, (a, item))| (file.clone(), (a.clone(), item.clone()), true));
    let shader_units = sources
        .into_iter()
        .flat_map(|(file, modules)| modules.into_iter().map(move |m| (file.clone(), m, false)));
    let available: Vec<DslModule> = libraries.iter().map(|(_, m)| m.clone()).collect();
    let doc_dir = out.join("doc");
    let mut documented = Vec::new();
    for (file, (args_tokens, item), is_library) in library_units.chain(shader_units) {
        let name = item.ident.to_string();
        if args.module.as_deref().is_some_and(|m| !name.contains(m)) {
            continue;
        }
        let compiled = if is_library {
            codegen::compile_library_with_libraries(args_tokens, &item, &available)
        } else {
            codegen::compile_with_libraries(args_tokens, &item, &available)
        }
        .map_err(|e| anyhow::anyhow!("{}: module `{name}`: {e}", file.display()))?;
        let dir = out.join(&name);
        std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
        for v in &compiled.variants {
            let stem = dir.join(&v.names[0]);
            std::fs::write(stem.with_extension("wgsl"), &v.wgsl)?;
            let spv_path = stem.with_extension("spv");
            std::fs::write(&spv_path, bytemuck_words(&v.spirv))?;
            if have_dis {
                let dis = Command::new("spirv-dis").arg(&spv_path).output()?;
                std::fs::write(stem.with_extension("spvasm"), dis.stdout)?;
            }
            rows.push(Row {
                module: if is_library {
                    format!("{name} (library)")
                } else {
                    name.clone()
                },
                names: v.names.clone(),
                wgsl_bytes: v.wgsl.len(),
                spirv_words: v.spirv.len(),
                workgroup: workgroup(&v.reflection.entry_points),
                bindings: bindings(&v.reflection.bindings),
                features: crate::shaders_doc::features(v.reflection.features),
                spirv_val: if have_val {
                    spirv_val(&spv_path, v.spirv_version, is_library)?
                } else {
                    SpirvVal::NotInstalled
                },
                gen_time: v.gen_time,
            });
        }
        if args.doc {
            let validation: Vec<crate::shaders_doc::Validation> = rows
                [rows.len() - compiled.variants.len()..]
                .iter()
                .map(|r| crate::shaders_doc::Validation {
                    spirv_val: match r.spirv_val {
                        SpirvVal::Passed => "ok",
                        SpirvVal::Failed(_) => "FAILED",
                        SpirvVal::NotInstalled => "not installed",
                    },
                    message: match &r.spirv_val {
                        SpirvVal::Failed(m) => Some(m.clone()),
                        _ => None,
                    },
                })
                .collect();
            let page = crate::shaders_doc::module_page(&compiled, &item, is_library, &validation);
            std::fs::create_dir_all(&doc_dir)
                .with_context(|| format!("creating {}", doc_dir.display()))?;
            std::fs::write(doc_dir.join(format!("{name}.md")), page)?;
            documented.push((name.clone(), compiled.variants.len(), is_library));
        }
    }
    if args.doc {
        std::fs::write(
            doc_dir.join("index.md"),
            crate::shaders_doc::index_page(&documented),
        )?;
        println!(
            "wrote {} module page(s) and index.md to {}",
            documented.len(),
            doc_dir.display()
        );
    }
    print_table(&rows);
    println!("\nwrote {} variant(s) to {}", rows.len(), out.display());
    print_timing(&rows);
    let failures: Vec<&Row> = rows
        .iter()
        .filter(|r| matches!(r.spirv_val, SpirvVal::Failed(_)))
        .collect();
    for r in &failures {
        if let SpirvVal::Failed(msg) = &r.spirv_val {
            println!("spirv-val rejected {}::{}:\n{msg}", r.module, r.names[0]);
        }
    }
    if args.check {
        if !have_val {
            bail!("--check needs spirv-val: install the Debian/Ubuntu package spirv-tools");
        }
        if !failures.is_empty() {
            bail!("spirv-val rejected {} variant(s)", failures.len());
        }
        println!("spirv-val: all {} variant(s) valid", rows.len());
    }
    Ok(())
}

/// Every `#[shader(..)] mod` (and `#[material(..)] mod`, expanded) in the `.rs` files under
/// `dir`, with its attribute arguments.
pub(crate) type DslModule = (proc_macro2::TokenStream, syn::ItemMod);

pub(crate) fn dsl_modules(dir: &Path) -> Result<Vec<(PathBuf, Vec<DslModule>)>> {
    let mut out = Vec::new();
    for file in rust_files(dir)? {
        let text = std::fs::read_to_string(&file)?;
        let parsed =
            syn::parse_file(&text).with_context(|| format!("parsing {}", file.display()))?;
        // Materials come as the `#[shader]` modules they expand to.
        let modules: Vec<DslModule> = codegen::shader_modules(&parsed);
        if !modules.is_empty() {
            out.push((file, modules));
        }
    }
    Ok(out)
}

/// The `.rs` files under `dir`, sorted.
pub(crate) fn rust_files(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).with_context(|| format!("reading {}", d.display()))? {
            let path = entry?.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    files.sort();
    Ok(files)
}

/// Every `#[shader_dsl::library]` module under `dir`, with its file (attribute removed).
pub(crate) fn dsl_libraries(dir: &Path) -> Result<Vec<(PathBuf, DslModule)>> {
    let mut out = Vec::new();
    for file in rust_files(dir)? {
        let text = std::fs::read_to_string(&file)?;
        let parsed =
            syn::parse_file(&text).with_context(|| format!("parsing {}", file.display()))?;
        out.extend(
            codegen::library_modules(&parsed)
                .into_iter()
                .map(|m| (file.clone(), m)),
        );
    }
    Ok(out)
}

/// Every module `shaders_gen::MODULES` exports must have been found in the sources, or the
/// table would silently leave it out; and every module of the sources must be in
/// `shaders_gen::MODULES`, or the snapshots, hot reload and the tools that walk it would.
pub(crate) fn check_all_modules_found(sources: &[(PathBuf, Vec<DslModule>)]) -> Result<()> {
    let found: Vec<String> = sources
        .iter()
        .flat_map(|(_, modules)| modules.iter().map(|(_, m)| m.ident.to_string()))
        .collect();
    let missing: Vec<&str> = shaders_gen::MODULES
        .iter()
        .map(|m| m.name)
        .filter(|name| !found.iter().any(|f| f == name))
        .collect();
    if !missing.is_empty() {
        bail!(
            "shaders_gen exports {missing:?}, but no `#[shader] mod` of that name was found under shaders_gen/src"
        );
    }
    let unlisted: Vec<&String> = found
        .iter()
        .filter(|f| !shaders_gen::MODULES.iter().any(|m| m.name == f.as_str()))
        .collect();
    if !unlisted.is_empty() {
        bail!(
            "shaders_gen/src defines the modules {unlisted:?}, which `shaders_gen::MODULES` does not list"
        );
    }
    Ok(())
}

fn bytemuck_words(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

fn tool_available(tool: &str) -> bool {
    Command::new(tool)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Runs spirv-val for the Vulkan environment matching the module's SPIR-V version.
/// Validates a variant for Vulkan; a library (no entry points, so naga declares the `Linkage`
/// capability that Vulkan rejects) is validated for the universal environment of its version.
fn spirv_val(path: &Path, version: (u8, u8), library: bool) -> Result<SpirvVal> {
    let env = match (library, version >= (1, 3)) {
        (true, true) => "spv1.3",
        (true, false) => "spv1.0",
        (false, true) => "vulkan1.1",
        (false, false) => "vulkan1.0",
    };
    let out = Command::new("spirv-val")
        .args(["--target-env", env])
        .arg(path)
        .output()
        .context("running spirv-val")?;
    Ok(if out.status.success() {
        SpirvVal::Passed
    } else {
        SpirvVal::Failed(String::from_utf8_lossy(&out.stderr).into_owned())
    })
}

fn workgroup(entries: &[codegen::reflect::EntryPointInfo]) -> String {
    let sizes: Vec<String> = entries
        .iter()
        .filter(|e| e.stage == codegen::rt::Stage::Compute)
        .map(|e| {
            format!(
                "{}x{}x{}",
                e.workgroup_size[0], e.workgroup_size[1], e.workgroup_size[2]
            )
        })
        .collect();
    if sizes.is_empty() {
        "-".into()
    } else {
        sizes.join(",")
    }
}

fn bindings(list: &[codegen::reflect::BindingInfo]) -> String {
    list.iter()
        .map(|b| {
            let kind = match b.kind {
                BindingKind::Uniform { .. } => "uniform",
                BindingKind::Storage {
                    read_only: true, ..
                } => "storage",
                BindingKind::Storage {
                    read_only: false, ..
                } => "storage_rw",
                BindingKind::Texture {
                    multisampled: true, ..
                } => "texture_ms",
                BindingKind::Texture { .. } => "texture",
                BindingKind::StorageTexture { .. } => "storage_texture",
                BindingKind::Sampler { comparison: true } => "sampler_cmp",
                BindingKind::Sampler { comparison: false } => "sampler",
            };
            format!("{}.{}:{kind}", b.group, b.binding)
        })
        .collect::<Vec<_>>()
        .join(" ")
}

#[expect(clippy::print_stdout, reason = "command-line report")]
fn print_table(rows: &[Row]) {
    println!(
        "| module | variant | WGSL bytes | SPIR-V words | workgroup | bindings | features | naga | spirv-val | gen ms |"
    );
    println!("|---|---|---:|---:|---|---|---|---|---|---:|");
    for r in rows {
        let val = match &r.spirv_val {
            SpirvVal::Passed => "ok",
            SpirvVal::Failed(_) => "FAILED",
            SpirvVal::NotInstalled => "not installed",
        };
        let name = if r.names.len() > 1 {
            format!("{} (= {})", r.names[0], r.names[1..].join(", "))
        } else {
            r.names[0].clone()
        };
        println!(
            "| {} | {name} | {} | {} | {} | {} | {} | ok | {val} | {:.3} |",
            r.module,
            r.wgsl_bytes,
            r.spirv_words,
            r.workgroup,
            r.bindings,
            r.features,
            r.gen_time.as_secs_f64() * 1e3
        );
    }
}

#[expect(clippy::print_stdout, reason = "command-line report")]
fn print_timing(rows: &[Row]) {
    let mut times: Vec<f64> = rows
        .iter()
        .map(|r| r.gen_time.as_secs_f64() * 1e3)
        .collect();
    if times.is_empty() {
        return;
    }
    times.sort_by(f64::total_cmp);
    let median = times[times.len() / 2];
    let total: f64 = times.iter().sum();
    let profile = if cfg!(debug_assertions) {
        "dev profile, codegen and naga at opt-level 3"
    } else {
        "release"
    };
    println!(
        "generation per variant (print + naga validate + SPIR-V + reflect): median {median:.3} ms, \
         max {:.3} ms, total {total:.1} ms over {} variant(s) [{profile}]",
        times[times.len() - 1],
        times.len()
    );
}
