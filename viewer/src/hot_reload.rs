//! Hot reload of the DSL shaders: the viewer watches the `shaders_gen` sources and, when a file
//! changes, compiles every DSL module again with the DSL compiler as a library (`codegen`, the
//! same code the proc-macro runs), and installs the variants whose WGSL changed
//! (`renderer::shader::hot`). The app then rebuilds its renderer, whose pipelines take the new
//! WGSL. No dylib, no restart: a change shows within the time of one compile (well under a
//! second for the whole `shaders_gen`) plus a renderer rebuild.
//!
//! The watch is event-driven and off the UI thread: `notify` (inotify on Linux) reports
//! file-system events, its debouncer merges a burst of them (an editor's truncate, write and
//! rename) into one, and a worker thread reads the sources, compiles and installs when their
//! text differs from the last compiled one, then sends the [`Outcome`] over a channel. The UI
//! thread only drains that channel ([`Watch::poll`] never blocks), so a compile never stalls a
//! frame. Installing is all-or-nothing and keeps every interface, so a renderer the UI thread
//! builds meanwhile is valid either way; the next outcome makes it rebuild on the new WGSL.
//!
//! An edit that does not compile, or that changes what host code relies on (entry points,
//! bindings), is reported with the DSL's message and source position, and nothing is
//! installed: the last good pipelines keep running. Struct layouts are part of the generated
//! host code, so edits to them need a rebuild of the program (the interface check refuses
//! those that would change a binding).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender, TryRecvError, channel};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use notify_debouncer_full::notify::event::{EventKind, ModifyKind};
use notify_debouncer_full::notify::{RecommendedWatcher, RecursiveMode};
use notify_debouncer_full::{
    DebounceEventResult, DebouncedEvent, Debouncer, RecommendedCache, new_debouncer,
};
use renderer::shader::hot::{BindingInterface, EntryInterface, Interface, Replacement};

/// How long the debouncer waits after a file's last event before it reports the file (an
/// editor's save is several events within a few milliseconds).
pub const DEBOUNCE: Duration = Duration::from_millis(100);

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
    /// The file-system watch reported an error (the watch goes on).
    WatchError(String),
}

/// Watches a folder of DSL sources: a `notify` debouncer feeds a worker thread that reloads;
/// its outcomes wait in a channel for [`Watch::poll`].
#[derive(Debug)]
pub struct Watch {
    dir: PathBuf,
    outcomes: Receiver<Outcome>,
    /// Dropping it stops the debouncer's thread, whose end closes the worker's events.
    debouncer: Option<Debouncer<RecommendedWatcher, RecommendedCache>>,
    worker: Option<JoinHandle<()>>,
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

/// The text of every `.rs` file under `dir`, by path.
type Sources = BTreeMap<PathBuf, String>;

fn sources(dir: &Path) -> Result<Sources, String> {
    let mut files = vec![];
    rust_files(dir, &mut files).map_err(|e| format!("{}: {e}", dir.display()))?;
    files
        .into_iter()
        .map(|f| match std::fs::read_to_string(&f) {
            Ok(text) => Ok((f, text)),
            Err(e) => Err(format!("{}: {e}", f.display())),
        })
        .collect()
}

/// Whether an event can change a source's text: a file or folder created, written, renamed or
/// removed. Opens, reads and closes (the worker's own reads among them) and metadata changes
/// (a `touch`) cannot, and other files (an editor's swap file) are not sources.
fn may_change_sources(event: &DebouncedEvent) -> bool {
    let source = |p: &PathBuf| p.extension().is_none_or(|e| e == "rs");
    match event.kind {
        EventKind::Access(_) | EventKind::Modify(ModifyKind::Metadata(_)) => false,
        // A rename names both ends: either may be a source.
        _ => event.paths.iter().any(source),
    }
}

/// Waits until no event that may change a source has come for [`DEBOUNCE`]: the debouncer
/// reports each event once it is that old, so a save spread over time can arrive in parts
/// (batches that queued during the last compile are taken at once). `false` when the debouncer
/// has stopped.
fn settle(events: &Receiver<DebounceEventResult>) -> bool {
    let mut quiet_from = Instant::now() + DEBOUNCE;
    loop {
        match events.recv_timeout(quiet_from.saturating_duration_since(Instant::now())) {
            Ok(Ok(batch)) if batch.iter().any(may_change_sources) => {
                quiet_from = Instant::now() + DEBOUNCE;
            }
            Ok(_) => {}
            Err(RecvTimeoutError::Timeout) => return true,
            Err(RecvTimeoutError::Disconnected) => return false,
        }
    }
}

/// The worker: waits for debounced events, and reloads when the sources' text differs from the
/// last state it saw (`seen`, at first the state when the watch started). Ends when the
/// debouncer stops or the [`Watch`] is gone.
fn work(
    dir: &Path,
    mut seen: Option<Sources>,
    events: &Receiver<DebounceEventResult>,
    outcomes: &Sender<Outcome>,
) {
    while let Ok(batch) = events.recv() {
        match batch {
            Err(errors) => {
                let errors: Vec<String> = errors.iter().map(ToString::to_string).collect();
                let message = format!("watching {}: {}", dir.display(), errors.join("; "));
                if outcomes.send(Outcome::WatchError(message)).is_err() {
                    return;
                }
                continue;
            }
            Ok(events) if !events.iter().any(may_change_sources) => continue,
            Ok(_) => {}
        }
        if !settle(events) {
            return;
        }
        let outcome = match sources(dir) {
            Ok(now) if seen.as_ref() == Some(&now) => continue,
            Ok(now) => {
                let outcome = match reload_sources(dir, &now) {
                    Ok(n) => Outcome::Installed(n),
                    Err(message) => Outcome::Refused(message),
                };
                seen = Some(now);
                outcome
            }
            // A folder that cannot be read (a save under way): refused; the next readable state
            // counts as a change.
            Err(message) => {
                seen = None;
                Outcome::Refused(message)
            }
        };
        if outcomes.send(outcome).is_err() {
            return;
        }
    }
}

impl Watch {
    /// Starts watching `dir` (its current state is the baseline: nothing is reloaded yet).
    pub fn new(dir: PathBuf) -> Result<Watch, String> {
        let baseline = sources(&dir).ok();
        let (events_in, events) = channel();
        let mut debouncer = new_debouncer(DEBOUNCE, None, events_in)
            .map_err(|e| format!("cannot watch {}: {e}", dir.display()))?;
        debouncer
            .watch(&dir, RecursiveMode::Recursive)
            .map_err(|e| format!("cannot watch {}: {e}", dir.display()))?;
        let (outcomes_in, outcomes) = channel();
        let worker_dir = dir.clone();
        let worker = std::thread::Builder::new()
            .name("shader hot reload".to_owned())
            .spawn(move || work(&worker_dir, baseline, &events, &outcomes_in))
            .map_err(|e| format!("cannot start the hot reload thread: {e}"))?;
        Ok(Watch {
            dir,
            outcomes,
            debouncer: Some(debouncer),
            worker: Some(worker),
        })
    }

    /// The folder watched.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The next reload the worker finished since the last call, if any; never waits.
    pub fn poll(&mut self) -> Option<Outcome> {
        match self.outcomes.try_recv() {
            Ok(outcome) => Some(outcome),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => {
                // The worker ended (its thread panicked): say so once.
                self.worker.take().map(|w| {
                    let _ = w.join();
                    Outcome::WatchError("the hot reload thread ended".to_owned())
                })
            }
        }
    }
}

impl Drop for Watch {
    fn drop(&mut self) {
        // Stopping the debouncer closes the worker's events; a compile under way finishes first.
        drop(self.debouncer.take());
        if let Some(worker) = self.worker.take() {
            let _ = worker.join();
        }
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
    reload_sources(dir, &sources(dir)?)
}

/// [`reload`] of the sources' text as read (`dir` only names the files in messages).
fn reload_sources(dir: &Path, sources: &Sources) -> Result<usize, String> {
    let mut parsed = vec![];
    for (file, text) in sources {
        let syntax = syn::parse_file(text).map_err(|e| located(dir, file, &e))?;
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
