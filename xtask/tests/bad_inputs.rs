//! Every option of `cargo xtask render` (and so of `demo`) refuses a bad value with a message
//! naming the option and what it accepts, and a failing exit code: the binary itself is run,
//! as a user would run it. Values that need the device (MSAA it lacks, light counts past its
//! buffer limit) are checked against the real adapter (lavapipe in CI).

use std::process::Command;

fn xtask(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(args)
        .output()
        .expect("the xtask binary runs");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.code().unwrap_or(-1), text)
}

/// Runs `render` with `args` and checks that it fails saying `expected`.
fn refused(args: &[&str], expected: &str) {
    let mut all = vec!["render"];
    all.extend(args);
    let (code, text) = xtask(&all);
    assert_ne!(code, 0, "{args:?} must fail, printed:\n{text}");
    assert!(
        text.contains(expected),
        "{args:?}: the message must contain {expected:?}, got:\n{text}"
    );
    assert!(
        !text.contains("panicked"),
        "{args:?} must be an error, not a panic:\n{text}"
    );
}

#[test]
fn every_option_refuses_bad_values_with_a_clear_message() {
    refused(
        &["--size", "0x10"],
        "size \"0x10\": use WxH with each side 1..=8192",
    );
    refused(&["--size", "9000x100"], "each side 1..=8192");
    refused(&["--size", "wide"], "use WxH");
    refused(&["--msaa", "3"], "--msaa 3: use 1, 2, 4 or 8");
    refused(&["--tile", "7"], "--tile 7: --path tiled takes [8, 16, 32]");
    refused(
        &["--path", "warp"],
        "path \"warp\": use one of naive, naive-prez, tiled, 2.5d, clustered, tbdr, tbdr-per-sample, \
         deferred, visibility",
    );
    refused(
        &["--view", "x"],
        "--view \"x\": use lit, heatmap, decals, shadow-atlas, particle-atlas or \
         shading-frequency",
    );
    refused(
        &["--view", "shading-frequency"],
        "--view shading-frequency: use --path tbdr, tbdr-per-sample, deferred or visibility",
    );
    refused(
        &["--path", "tbdr", "--tile", "32"],
        "--tile 32: --path tbdr takes [8, 16]",
    );
    refused(
        &["--view", "particle-atlas"],
        "--view particle-atlas: the frame has no particles; add --particles N",
    );
    refused(
        &["--particle-lighting", "x"],
        "--particle-lighting: particle lighting \"x\": use atlas or per-pixel",
    );
    refused(
        &["--particle-atlas", "100"],
        "--particle-atlas 100: use a power of two from 64 to 4096, or 0 for the default",
    );
    refused(
        &["--scalarize", "maybe"],
        "--scalarize \"maybe\": use auto, on or off",
    );
    refused(
        &["--light-radius", "2,1"],
        "give MIN,MAX with 0 < MIN <= MAX",
    );
    refused(&["--light-radius", "50"], "MIN,MAX (two numbers");
    refused(&["--eye", "1,2,3"], "--target");
    refused(
        &["--eye", "1,2", "--target", "0,0,0"],
        "X,Y,Z (three numbers",
    );
    refused(&["--exposure", "40"], "between -16 and 16 stops");
    refused(&["--camera", "3"], "--camera 3: the scene has 1 camera(s)");
    refused(&["--lights", "many"], "invalid value 'many' for '--lights");
    refused(&["--scene", "/nonexistent/scene.glb"], "no such file");
    refused(
        &["--decals-file", "/nonexistent/decals.json"],
        "--decals-file /nonexistent/decals.json",
    );
    refused(&["--decals", "lots"], "invalid value 'lots' for '--decals");
    refused(
        &["--adapter", "no-such-gpu-anywhere"],
        "no-such-gpu-anywhere",
    );
}

#[test]
fn the_demo_refuses_bad_values_too() {
    for (args, expected) in [
        (
            &["demo", "--exposure", "40"][..],
            "between -16 and 16 stops",
        ),
        (&["demo", "--exposure", "bright"][..], "a number of stops"),
        (
            &["demo", "--adapter", "no-such-gpu-anywhere"][..],
            "no-such-gpu-anywhere",
        ),
    ] {
        let (code, text) = xtask(args);
        assert_ne!(code, 0, "{args:?} must fail:\n{text}");
        assert!(
            text.contains(expected),
            "{args:?}: want {expected:?} in:\n{text}"
        );
    }
}

#[test]
fn a_malformed_scene_file_is_an_error_naming_it() {
    let dir = std::env::temp_dir().join(format!("xtask-bad-inputs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let file = dir.join("broken.glb");
    std::fs::write(&file, b"glTF\x02\x00\x00\x00 this is not a binary glTF").expect("write");
    let path = file.to_string_lossy().into_owned();
    refused(
        &["--scene", &path],
        &format!("--scene {path}: cannot load it"),
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn device_limits_are_checked_before_allocating() {
    let gpu = renderer::GpuContext::new_blocking(&renderer::GpuOptions::from_env())
        .expect("a GPU adapter (lavapipe in CI)");
    let most = renderer::frame_data::LightSet::max_lights(gpu.device());
    let past = (most + 1).to_string();
    refused(
        &["--lights", &past],
        &format!("this device holds at most {most} lights"),
    );
    let counts = gpu.capabilities().msaa_counts();
    match [2, 8].into_iter().find(|c| !counts.contains(c)) {
        Some(missing) => refused(
            &["--msaa", &missing.to_string()],
            &format!("--msaa {missing}: this adapter supports MSAA {counts:?}"),
        ),
        // An adapter with every count: the option is accepted and renders.
        None => {
            let out = std::env::temp_dir().join(format!("xtask-msaa8-{}.png", std::process::id()));
            let out_arg = out.to_string_lossy().into_owned();
            let (code, text) = xtask(&[
                "render", "--msaa", "8", "--size", "64x36", "--lights", "8", "--out", &out_arg,
            ]);
            assert_eq!(code, 0, "{text}");
            std::fs::remove_file(&out).ok();
        }
    }
}
