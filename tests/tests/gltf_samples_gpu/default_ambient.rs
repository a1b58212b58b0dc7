//! The sky and ground ambient (`RendererConfig::ambient`), which is all that lights a file scene
//! without lights of its own:
//! * with the default, such a scene (Khronos's `BoxVertexColors`) is plainly visible; with the
//!   ambient off it is black;
//! * a surface facing up gets the sky's radiance, one facing down the ground's, and an upright
//!   one their mean, times its base colour: pixels of a floor, a ceiling and a wall against
//!   that arithmetic through the ACES curve and the sRGB encoding, written out here, on the
//!   forward path and through the G-buffer of both deferred paths.

use glam::Vec3;
use renderer::frame::{Ambient, FrameCamera, RenderPath, RendererConfig};
use renderer::scene::procedural::SceneBuilder;
use tests::frames::{render_frame, render_frame_from};
use tests::gpu::gpu_test;

use super::sample;

/// Rec. 709 luma of 8-bit RGB.
fn luma(p: &[u8]) -> f32 {
    0.2126 * f32::from(p[0]) + 0.7152 * f32::from(p[1]) + 0.0722 * f32::from(p[2])
}

#[test]
fn a_file_scene_without_lights_shows_by_the_default_ambient_and_is_black_without_it() {
    let scene = sample("BoxVertexColors/BoxVertexColors.glb");
    assert!(scene.lights.is_empty(), "the sample must have no lights");
    let config = |ambient| RendererConfig {
        width: 160,
        height: 120,
        ambient,
        ..Default::default()
    };
    gpu_test(|gpu| {
        let lit = render_frame(gpu, &scene, config(Ambient::default()), &[]).rgba;
        let dark = render_frame(gpu, &scene, config(Ambient::OFF), &[]).rgba;
        let covered = dark.len() / 4 - lit.chunks_exact(4).filter(|p| luma(p) < 1.0).count();
        let mean = lit
            .chunks_exact(4)
            .filter(|p| luma(p) >= 1.0)
            .map(luma)
            .sum::<f32>()
            / covered.max(1) as f32;
        let brightest = dark.chunks_exact(4).map(|p| p[0].max(p[1]).max(p[2])).max();
        eprintln!(
            "default: {covered} pixels covered, mean luma {mean:.1}; off: brightest {brightest:?}"
        );
        assert!(
            covered > 4000 && mean > 60.0,
            "with the default ambient the unlit box must be plainly visible: {covered} pixels \
             covered, mean luma {mean:.1}"
        );
        assert_eq!(
            brightest,
            Some(0),
            "with the ambient off, a scene without lights or emission must be black"
        );
    });
}

/// ACES filmic (Narkowicz's fit), clamped to [0, 1]: the tonemapper's curve.
fn aces(x: f32) -> f32 {
    ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// The sRGB transfer function, to 8 bits.
fn srgb8(l: f32) -> f32 {
    let s = if l <= 0.003_130_8 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round()
}

#[test]
fn surfaces_facing_up_get_the_sky_and_facing_down_the_ground() {
    let sky = Vec3::new(0.6, 0.3, 0.1);
    let ground = Vec3::new(0.04, 0.12, 0.5);
    let albedo = Vec3::new(0.8, 0.7, 0.9);
    // A floor at y = −1 (facing up), a ceiling at y = 1 (facing down) and a wall at z = −2
    // (facing the camera), all of one rough dielectric of base colour `albedo`.
    let mut b = SceneBuilder::new();
    let m = b.material("matte", albedo, 1.0);
    b.cuboid(Vec3::new(-4.0, -1.0, -3.0), Vec3::new(4.0, -1.0, 4.0), m);
    b.cuboid(Vec3::new(-4.0, 1.0, -3.0), Vec3::new(4.0, 1.0, 4.0), m);
    b.cuboid(Vec3::new(-4.0, -3.0, -2.0), Vec3::new(4.0, 3.0, -2.0), m);
    let scene = b.build();
    let (w, h) = (96, 96);
    let camera = FrameCamera::look_at(
        Vec3::new(0.0, 0.0, 3.0),
        Vec3::ZERO,
        Vec3::Y,
        60f32.to_radians(),
        1.0,
        (0.1, 20.0),
    );
    // Expected 8-bit sRGB of a surface of ambient radiance `a` (exposure 1).
    let expect = |a: Vec3| (a * albedo).to_array().map(|c| srgb8(aces(c)));
    let cases = [
        ("floor (facing up): sky", h - 6, expect(sky)),
        ("ceiling (facing down): ground", 5, expect(ground)),
        (
            "wall (upright): the mean",
            h / 2,
            expect((sky + ground) * 0.5),
        ),
    ];
    gpu_test(|gpu| {
        for path in [RenderPath::Tiled, RenderPath::Tbdr, RenderPath::Deferred] {
            let config = RendererConfig {
                width: w,
                height: h,
                msaa: 1,
                path,
                ambient: Ambient { sky, ground },
                ..Default::default()
            };
            let frame = render_frame_from(gpu, &scene, config, &[], &camera);
            for (what, y, want) in cases {
                let p = &frame.rgba[((y * w + w / 2) * 4) as usize..][..3];
                let got = [p[0], p[1], p[2]].map(f32::from);
                let off = got
                    .iter()
                    .zip(want)
                    .map(|(g, w)| (g - w).abs())
                    .fold(0.0, f32::max);
                eprintln!("{} {what}: got {got:?}, want {want:?}", path.name());
                assert!(
                    off <= 2.0,
                    "{} {what}: got {got:?}, want {want:?} (ambient × base colour through ACES \
                     and sRGB)",
                    path.name()
                );
            }
        }
    });
}
