//! The hot reload watch without a window: `notify` events on a copy of the `shaders_gen`
//! sources reach the worker thread, which compiles off the caller's thread. A save made of
//! several writes is one reload, a save that changes no text (or a file that is not a source)
//! is none, a broken edit is refused with its position, and `Watch::poll` never waits, not even
//! while a compile is under way. A second watcher (plain `notify`) sees every open of the
//! sources: once a reload is done, the watch reads nothing until the next edit (its own reads
//! must not wake it). An edit to a library reached through other libraries reloads exactly
//! the variants that print it.

use std::path::Path;
use std::sync::mpsc::Receiver;
use std::time::{Duration, Instant};

use notify_debouncer_full::notify::event::{AccessKind, EventKind};
use notify_debouncer_full::notify::{self, RecursiveMode, Watcher as _};
use viewer::hot_reload::{DEBOUNCE, Outcome, Watch};

const TONEMAP: &str = "forward/tonemapping.rs";
/// The edit site: `tone_curves::tone_mapped`, the library both tonemaps (the full-screen pass
/// and the compute kernel) use, so the edit shows whichever runs.
const ORIGINAL: &str = "let c = hdr.max(Vec3::ZERO) * exposure;";
const TINTED: &str = "let c = hdr.max(Vec3::ZERO) * exposure * Vec3::new(1.0, 0.25, 0.25);";
const BROKEN: &str = "let c = undefined_tint(hdr) * exposure;";
/// `surface_light::light_contribution`'s result, and an edit of it.
const RESPONSE: &str = "radiance * visibility\n";
const HALVED: &str = "radiance * visibility * 0.5\n";
/// The hot-reload table is global: the tests that install replacements take turns.
static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());
/// The longest one `poll` may take: a channel read, far below one compile.
const POLL_AT_MOST: Duration = Duration::from_millis(50);

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("create the copy");
    for entry in std::fs::read_dir(from).expect("read the sources") {
        let path = entry.expect("entry").path();
        let target = to.join(path.file_name().expect("a name"));
        if path.is_dir() {
            copy_dir(&path, &target);
        } else {
            std::fs::copy(&path, &target).expect("copy a source");
        }
    }
}

/// Polls every 5 ms for `span`: what came, and the longest single `poll`.
fn poll_for(watch: &mut Watch, span: Duration) -> (Vec<Outcome>, Duration) {
    let (started, mut slowest, mut seen) = (Instant::now(), Duration::ZERO, vec![]);
    while started.elapsed() < span {
        let t = Instant::now();
        let outcome = watch.poll();
        slowest = slowest.max(t.elapsed());
        seen.extend(outcome);
        std::thread::sleep(Duration::from_millis(5));
    }
    (seen, slowest)
}

/// Polls until an outcome comes (at most 120 s): it, the longest `poll`, and the wait.
fn next(watch: &mut Watch) -> (Outcome, Duration, Duration) {
    let (started, mut slowest) = (Instant::now(), Duration::ZERO);
    loop {
        let t = Instant::now();
        let outcome = watch.poll();
        slowest = slowest.max(t.elapsed());
        if let Some(o) = outcome {
            return (o, slowest, started.elapsed());
        }
        assert!(
            started.elapsed() < Duration::from_secs(120),
            "no reload 120 s after the edit"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// The opens of files under the copy since the last call, as a second watcher saw them.
fn opens(raw: &Receiver<notify::Result<notify::Event>>) -> usize {
    raw.try_iter()
        .filter(|e| {
            e.as_ref()
                .is_ok_and(|e| matches!(e.kind, EventKind::Access(AccessKind::Open(_))))
        })
        .count()
}

/// Writes `text` the way an editor may: truncate, a partial write, then the whole file.
fn save_in_pieces(file: &Path, text: &str) {
    std::fs::write(file, "").expect("truncate");
    std::fs::write(file, &text[..text.len() / 2]).expect("a partial write");
    std::fs::write(file, text).expect("the whole file");
}

#[test]
fn each_saved_change_is_one_reload_off_the_polling_thread() {
    let _serial = SERIAL
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let dir = std::env::temp_dir().join(format!("viewer-watch-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    copy_dir(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../shaders_gen/src"),
        &dir,
    );
    let tonemap = dir.join(TONEMAP);
    let original = std::fs::read_to_string(&tonemap).expect("the tonemap source");
    assert!(original.contains(ORIGINAL), "the edit site moved");
    let mut watch = Watch::new(dir.clone()).expect("watch the copy");
    let (raw_in, raw) = std::sync::mpsc::channel();
    let mut second = notify::recommended_watcher(raw_in).expect("a second watcher");
    second
        .watch(&dir, RecursiveMode::Recursive)
        .expect("watch the copy twice");

    // Nothing changed: nothing reported.
    let (quiet, _) = poll_for(&mut watch, Duration::from_millis(600));
    assert_eq!(quiet, vec![], "a reload without an edit");

    // A colour edit saved in three writes: one reload, compiled while `poll` kept returning.
    let tinted = original.replacen(ORIGINAL, TINTED, 1);
    save_in_pieces(&tonemap, &tinted);
    let (outcome, slowest, waited) = next(&mut watch);
    eprintln!(
        "reload after {:.0} ms; the slowest poll took {:?}",
        waited.as_secs_f64() * 1e3,
        slowest
    );
    let Outcome::Installed(replaced) = outcome else {
        panic!("the colour edit was not installed: {outcome:?}");
    };
    assert!(replaced > 0, "the colour edit replaced no variant");
    assert_eq!(renderer::shader::hot::installed(), replaced);
    assert!(
        waited >= DEBOUNCE,
        "reported after {waited:?}, before the debouncer's {DEBOUNCE:?}"
    );
    assert!(
        slowest < POLL_AT_MOST,
        "a poll took {slowest:?} while the edit compiled: it waited for the compile"
    );
    // The reload's own reads are over; from here on the copy is left alone.
    std::thread::sleep(Duration::from_millis(200));
    opens(&raw);
    let (more, _) = poll_for(&mut watch, Duration::from_millis(800));
    assert_eq!(more, vec![], "one save, more than one reload");
    let reads = opens(&raw);
    assert_eq!(
        reads, 0,
        "{reads} opens of the sources with no edit: the watch wakes itself"
    );

    // The same text saved again, and a file that is not a source: no reload.
    std::fs::write(&tonemap, &tinted).expect("save again");
    std::fs::write(dir.join("notes.txt"), "not a source").expect("a note");
    // (Longer than a compile, so that a reload of it would show.)
    let (none, _) = poll_for(&mut watch, Duration::from_secs(4));
    assert_eq!(none, vec![], "a save that changed no source text reloaded");

    // A broken edit: refused with the DSL's error at its position; the tint stays installed.
    std::fs::write(&tonemap, tinted.replacen(TINTED, BROKEN, 1)).expect("break it");
    let (outcome, _, _) = next(&mut watch);
    let Outcome::Refused(why) = outcome else {
        panic!("the broken edit was not refused: {outcome:?}");
    };
    assert!(
        why.contains("forward/tonemapping.rs:48:") && why.contains("undefined_tint"),
        "{why}"
    );
    assert_eq!(renderer::shader::hot::installed(), replaced);

    drop(second);
    // Dropping the watch stops its threads.
    let t = Instant::now();
    drop(watch);
    assert!(
        t.elapsed() < Duration::from_secs(30),
        "the watch did not stop"
    );
    renderer::shader::hot::clear();
    std::fs::remove_dir_all(&dir).ok();
}

/// An edit to a library that modules reach through other libraries (`surface_light`: used by
/// `forward` itself, and by `tbdr` and `light_volume` only through `tbdr_gbuffer`) reloads every
/// variant that prints the edited function, and no other.
#[test]
fn an_edit_to_a_library_reloads_every_module_that_reaches_it_through_the_graph() {
    let _serial = SERIAL
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let dir = std::env::temp_dir().join(format!("viewer-graph-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    copy_dir(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../shaders_gen/src"),
        &dir,
    );
    let lights = dir.join("shared/lights.rs");
    let original = std::fs::read_to_string(&lights).expect("the light libraries' source");
    assert_eq!(original.matches(RESPONSE).count(), 1, "the edit site moved");
    std::fs::write(&lights, original.replacen(RESPONSE, HALVED, 1)).expect("edit");
    let printing: Vec<(&str, &str)> = shaders_gen::MODULES
        .iter()
        .flat_map(|m| m.variants.iter().map(move |v| (m.name, v)))
        .filter(|(_, v)| v.wgsl.contains("fn light_contribution("))
        .map(|(m, v)| (m, v.name()))
        .collect();
    for module in ["forward", "tbdr", "light_volume"] {
        assert!(
            printing.iter().any(|(m, _)| *m == module),
            "{module} prints no light_contribution: {printing:?}"
        );
    }
    let replaced = viewer::hot_reload::reload(&dir).expect("the edited library compiles");
    assert_eq!(
        replaced,
        printing.len(),
        "variants replaced, against those printing the edited function"
    );
    renderer::shader::hot::clear();
    std::fs::remove_dir_all(&dir).ok();
}
