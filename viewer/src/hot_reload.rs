//! Hot reload of the DSL shaders: the viewer watches the `shaders_gen` sources and, when a file
//! changes, compiles every DSL module again with the DSL compiler as a library (`codegen`, the
//! same code the proc-macro runs), and installs the variants whose WGSL changed
//! (`renderer::shader::hot`). The app then rebuilds its renderer, whose pipelines take the new
//! WGSL. No dylib, no restart: a change shows within the time of one compile (well under a
//! second for the whole `shaders_gen`) plus a renderer rebuild.
//!
//! An edit that does not compile, or that changes what host code relies on (entry points,
//! bindings), is reported with the DSL's message and source position, and nothing is
//! installed: the last good pipelines keep running. Struct layouts are part of the generated
//! host code, so edits to them need a rebuild of the program (the interface check refuses
//! those that would change a binding).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};

use renderer::shader::hot::{BindingInterface, EntryInterface, Interface, Replacement};

/// How often the sources' modification times are read.
const POLL: Duration = Duration::from_millis(250);

/// The `shaders_gen` sources of this checkout, when they exist (a viewer run from its
/// workspace).
pub fn default_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shaders_gen/src");
    dir.is_dir().then_some(dir)
}

/// What one reload did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Outcome {
    /// These variants now use new WGSL (0: the edit changed no variant's WGSL).
    Installed(usize),
    /// Nothing changed; why.
    Refused(String),
}

/// Watches a folder of DSL sources.
#[derive(Debug)]
pub struct Watch {
    dir: PathBuf,
    stamps: BTreeMap<PathBuf, SystemTime>,
    polled: Instant,
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        if path.is_dir() {
            rust_files(&path, out)?;
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
    Ok(())
}

fn stamps(dir: &Path) -> BTreeMap<PathBuf, SystemTime> {
    let mut files = vec![];
    // A folder that cannot be read has no stamps: the next readable state counts as a change.
    let _ = rust_files(dir, &mut files);
    files
        .into_iter()
        .filter_map(|f| {
            let t = std::fs::metadata(&f).and_then(|m| m.modified()).ok()?;
            Some((f, t))
        })
        .collect()
}

impl Watch {
    /// Starts watching `dir` (its current state is the baseline: nothing is reloaded yet).
    pub fn new(dir: PathBuf) -> Watch {
        let stamps = stamps(&dir);
        Watch {
            dir,
            stamps,
            polled: Instant::now(),
        }
    }

    /// The folder watched.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Reloads when a source changed since the last poll (polls at most every 250 ms).
    pub fn poll(&mut self) -> Option<Outcome> {
        if self.polled.elapsed() < POLL {
            return None;
        }
        self.polled = Instant::now();
        let now = stamps(&self.dir);
        if now == self.stamps {
            return None;
        }
        self.stamps = now;
        Some(match reload(&self.dir) {
            Ok(n) => Outcome::Installed(n),
            Err(message) => Outcome::Refused(message),
        })
    }
}

/// `file:line:column: message` of a DSL error, the file relative to the watched folder.
fn located(dir: &Path, file: &Path, e: &syn::Error) -> String {
    let start = e.span().start();
    format!(
        "{}:{}:{}: {e}",
        file.strip_prefix(dir).unwrap_or(file).display(),
        start.line,
        start.column + 1
    )
}

/// Compiles every DSL module under `dir` and installs the variants whose WGSL differs from the
/// generated one; how many.
pub fn reload(dir: &Path) -> Result<usize, String> {
    let mut files = vec![];
    rust_files(dir, &mut files).map_err(|e| format!("{}: {e}", dir.display()))?;
    files.sort();
    let mut parsed = vec![];
    for file in &files {
        let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
        let syntax = syn::parse_file(&text).map_err(|e| located(dir, file, &e))?;
        parsed.push((file.clone(), syntax));
    }
    let libraries: Vec<_> = parsed
        .iter()
        .flat_map(|(_, f)| codegen::library_modules(f))
        .collect();
    let mut replacements = vec![];
    for (file, syntax) in &parsed {
        for (args, item) in codegen::shader_modules(syntax) {
            let compiled = codegen::compile_with_libraries(args, &item, &libraries)
                .map_err(|e| located(dir, file, &e))?;
            let name = item.ident.to_string();
            let Some(generated) = shaders_gen::MODULES.iter().find(|m| m.name == name) else {
                continue;
            };
            for v in &compiled.variants {
                let Some(old) = generated.variant_named(&v.names[0]) else {
                    continue;
                };
                if old.wgsl != v.wgsl {
                    replacements.push(Replacement {
                        module: name.clone(),
                        variant: v.names[0].clone(),
                        wgsl: v.wgsl.clone(),
                        interface: interface(&v.reflection),
                    });
                }
            }
        }
    }
    renderer::shader::hot::install_all(&replacements).map_err(|e| e.to_string())?;
    Ok(replacements.len())
}

/// The interface the DSL compiler reflects for a variant.
fn interface(r: &codegen::reflect::Reflection) -> Interface {
    Interface {
        entry_points: r
            .entry_points
            .iter()
            .map(|e| EntryInterface {
                name: e.name.clone(),
                stage: e.stage,
                workgroup_size: e.workgroup_size,
                inputs: e.inputs.clone(),
                outputs: e.outputs.clone(),
            })
            .collect(),
        bindings: r
            .bindings
            .iter()
            .map(|b| BindingInterface {
                group: b.group,
                binding: b.binding,
                kind: b.kind,
                visibility: b.visibility,
            })
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::{default_dir, reload};

    /// The unedited sources compile to exactly the generated WGSL: nothing to replace. (So a
    /// reload after an edit replaces only what the edit changed.)
    #[test]
    fn the_unedited_sources_replace_nothing() {
        let dir = default_dir().expect("the workspace's shaders_gen sources");
        assert_eq!(reload(&dir), Ok(0));
    }
}
