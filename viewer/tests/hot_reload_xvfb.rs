//! Shader hot reload in the running viewer, under Xvfb: the viewer watches a copy of the
//! `shaders_gen` sources; an edit of a colour constant in the tonemap shader changes what the
//! window shows without a restart, and a broken edit is reported with the DSL's error (in the
//! log and the overlay) while the last good pipeline keeps rendering the same frame.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const TONEMAP: &str = "forward/tonemapping.rs";
/// The edit site: `tone_curves::tone_mapped`, the library both tonemaps (the full-screen pass
/// and the compute kernel) use, so the edit shows whichever runs.
const ORIGINAL: &str = "let c = hdr.max(Vec3::ZERO) * exposure;";
/// The colour edit: a red tint.
const TINTED: &str = "let c = hdr.max(Vec3::ZERO) * exposure * Vec3::new(1.0, 0.25, 0.25);";
/// The broken edit: a function that does not exist.
const BROKEN: &str = "let c = undefined_tint(hdr) * exposure;";

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

fn edit(file: &Path, from: &str, to: &str) {
    let text = std::fs::read_to_string(file).expect("the tonemap source");
    assert!(text.contains(from), "the edit site `{from}` moved");
    std::fs::write(file, text.replacen(from, to, 1)).expect("edit the source");
}

fn wait_for(path: &Path, viewer: &mut std::process::Child, log: &Path) {
    let started = Instant::now();
    while !path.exists() {
        if let Ok(Some(status)) = viewer.try_wait() {
            panic!(
                "the viewer ended ({status}) before writing {}:\n{}",
                path.display(),
                std::fs::read_to_string(log).unwrap_or_default()
            );
        }
        assert!(
            started.elapsed() < Duration::from_secs(300),
            "no {} after 300 s:\n{}",
            path.display(),
            std::fs::read_to_string(log).unwrap_or_default()
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    // The PNG is written in one go after the file appears; give it a moment to complete.
    std::thread::sleep(Duration::from_millis(300));
}

fn rgba(path: &Path) -> image::RgbaImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8()
}

/// The mean of one channel over the image.
fn mean(img: &image::RgbaImage, channel: usize) -> f64 {
    let n = img.pixels().count().max(1) as f64;
    img.pixels().map(|p| f64::from(p.0[channel])).sum::<f64>() / n
}

#[test]
fn a_colour_edit_shows_without_a_restart_and_a_broken_edit_keeps_the_last_good_shader() {
    let dir = std::env::temp_dir().join(format!("viewer-hot-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let sources = dir.join("src");
    copy_dir(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../shaders_gen/src"),
        &sources,
    );
    let shots = dir.join("shots");
    let log = dir.join("viewer.log");
    let mut viewer = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 640x480x24"])
        .arg(env!("CARGO_BIN_EXE_viewer"))
        .args(["--size", "160x90", "--lights", "64", "--decals", "0"])
        .args(["--particles", "0", "--frames", "1000000"])
        .arg("--watch-shaders")
        .arg(&sources)
        .arg("--reload-shots")
        .arg(&shots)
        .args(["--exit-after-reloads", "2"])
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&log).expect("the log"))
        .spawn()
        .expect("xvfb-run runs (Debian package xvfb; cargo xtask test installs it)");
    let shot = |k: u32| shots.join(format!("reload-{k}.png"));
    let overlay = |k: u32| shots.join(format!("reload-{k}-overlay.png"));
    let tonemap: PathBuf = sources.join(TONEMAP);

    wait_for(&shot(0), &mut viewer, &log);
    let edited = Instant::now();
    edit(&tonemap, ORIGINAL, TINTED);
    wait_for(&shot(1), &mut viewer, &log);
    let shown_after = edited.elapsed();
    edit(&tonemap, TINTED, BROKEN);
    wait_for(&shot(2), &mut viewer, &log);
    let status = viewer.wait().expect("the viewer ends after two reloads");
    let text = std::fs::read_to_string(&log).unwrap_or_default();
    assert!(status.success(), "the viewer failed:\n{text}");
    eprintln!(
        "the colour edit showed {:.1} s after it was saved",
        shown_after.as_secs_f64()
    );

    // The tint took effect: green and blue fall, red does not.
    let (before, tinted) = (rgba(&shot(0)), rgba(&shot(1)));
    assert!(mean(&before, 1) > 20.0, "the first frame is lit");
    assert!(
        mean(&tinted, 1) < 0.8 * mean(&before, 1) && mean(&tinted, 2) < 0.8 * mean(&before, 2),
        "green {:.1} -> {:.1}, blue {:.1} -> {:.1}: the edit did not show",
        mean(&before, 1),
        mean(&tinted, 1),
        mean(&before, 2),
        mean(&tinted, 2)
    );
    assert!(mean(&tinted, 0) >= mean(&before, 0) - 1.0, "red stays");
    assert!(
        text.contains("shader variant(s) replaced"),
        "the log does not report the reload:\n{text}"
    );

    // The broken edit: refused with the DSL's error and position, the same frame rendered on.
    assert!(
        text.contains("shader edit refused") && text.contains("undefined_tint"),
        "the log does not show the DSL error:\n{text}"
    );
    assert!(
        text.contains("forward/tonemapping.rs:48:"),
        "the error has no source position:\n{text}"
    );
    assert!(
        rgba(&shot(2)).as_raw() == tinted.as_raw(),
        "the last good shader did not keep rendering"
    );
    // The overlay's first line is the reload message: it changed with the refusal.
    assert!(
        rgba(&overlay(2)).as_raw() != rgba(&overlay(1)).as_raw(),
        "the overlay does not show the error"
    );
    std::fs::remove_dir_all(&dir).ok();
}
