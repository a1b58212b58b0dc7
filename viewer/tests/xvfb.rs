//! The viewer for real: its binary runs under Xvfb (an X server without a screen) on the
//! adapter the tests use (lavapipe in CI), for a scripted number of frames with scripted input,
//! and writes a screenshot of its swapchain texture. The screenshot must equal a headless render,
//! through the same public API, of the same scene, lights and camera (the start camera moved by
//! the scripted keys with the fixed time step of scripted runs).

use std::process::Command;

use renderer::frame::create_target;
use renderer::frame::{Renderer, RendererConfig};
use renderer::{GpuContext, GpuOptions, readback};
use viewer::fly::Held;
use viewer::scene::{load, look};

const SIZE: (u32, u32) = (160, 90);
const LIGHTS: usize = 64;
/// Decals in both renders (the viewer's and the headless reference), so the comparison covers them.
const DECALS: usize = 48;

fn headless(steps: u32) -> Vec<u8> {
    // No particles: they advance a step per frame, so the viewer's sixth frame and a headless
    // first frame would differ by design.
    let shown = load(None, LIGHTS, DECALS, 0, 1).expect("the courtyard");
    let mut fly = shown.start;
    for _ in 0..steps {
        let held = Held {
            forward: true,
            ..Held::default()
        };
        fly.step(held, 1.0 / 60.0);
    }
    let gpu = GpuContext::new_blocking(&GpuOptions::from_env()).expect("a GPU adapter");
    let msaa = if gpu.capabilities().msaa_counts().contains(&4) {
        4
    } else {
        1
    };
    let config = RendererConfig {
        width: SIZE.0,
        height: SIZE.1,
        msaa,
        scalarize: gpu.capabilities().subgroup.is_some(),
        ..look(&shown)
    };
    let mut r = Renderer::new(&gpu, config).expect("renderer");
    r.prepare_scene(&shown.scene)
        .expect("the scene fits the device");
    r.set_lights(&shown.lights).expect("lights fit");
    r.set_decals(&shown.decals).expect("decals fit");
    let target = create_target(gpu.device(), &config);
    r.render(&fly.camera(SIZE.0 as f32 / SIZE.1 as f32), &target)
        .expect("frame");
    readback::read_texture_rgba8(gpu.device(), gpu.queue(), &target).expect("readback")
}

#[test]
fn the_viewer_under_xvfb_shows_what_the_headless_renderer_renders() {
    let dir = std::env::temp_dir().join(format!("viewer-xvfb-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let shot = dir.join("shot.png");
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 640x480x24"])
        .arg(env!("CARGO_BIN_EXE_viewer"))
        .args(["--size", &format!("{}x{}", SIZE.0, SIZE.1)])
        .args(["--lights", &LIGHTS.to_string()])
        .args(["--decals", &DECALS.to_string()])
        .args(["--particles", "0"])
        .args(["--frames", "6", "--script", "1:w x3"])
        .arg("--screenshot")
        .arg(&shot)
        .output()
        .expect("xvfb-run runs (Debian package xvfb; cargo xtask test installs it)");
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "the viewer failed:\n{log}");
    let seen = image::open(&shot).expect("the screenshot").to_rgba8();
    assert_eq!(seen.dimensions(), SIZE, "the window kept its size");
    let expected = headless(3);
    let worst = seen
        .as_raw()
        .iter()
        .zip(&expected)
        .map(|(a, b)| a.abs_diff(*b))
        .max()
        .unwrap_or(0);
    let lit = expected
        .chunks(4)
        .filter(|p| p[0] > 40 || p[1] > 40)
        .count();
    assert!(lit > 1000, "the reference frame is lit ({lit} pixels)");
    assert!(
        worst <= 1,
        "the viewer's frame differs from the headless one by {worst}"
    );
    // A camera that had not moved would not match: the script took effect.
    let unmoved = headless(0);
    assert_ne!(unmoved, expected, "three steps forward change the view");
    std::fs::remove_dir_all(&dir).ok();
}
