//! Sampling the decal atlas on the GPU. A decal stretched along a floor seen at a grazing angle
//! (where the sampler reads the smallest mip levels) shows exactly the same image whether its
//! material sits alone in the atlas or between neighbours of another colour: gutters stop every
//! level from filtering one decal into the next. And the gradients taken from the box projection
//! pick blurred levels for a fine pattern seen from afar, where level 0 would alias.

use glam::{Vec3, Vec3Swizzles as _};
use renderer::decals::{Decal, DecalAtlas, DecalAtlasConfig, DecalImage, DecalMaterial, DecalSet};
use renderer::frame::{FrameCamera, RenderPath, RendererConfig};
use renderer::scene::Scene;
use renderer::scene::procedural::SceneBuilder;
use tests::decal_stage::{flat_box, solid};
use tests::frames::{largest_difference, render_frame_with};
use tests::gpu::gpu_test;

/// A floor `half` units each way from the origin, of linear `color`.
fn floor(half: f32, color: Vec3) -> Scene {
    let mut b = SceneBuilder::new();
    let m = b.material("floor", color, 0.9);
    b.cuboid(Vec3::new(-half, 0.0, -half), Vec3::new(half, 0.0, half), m);
    b.build()
}

/// A camera at `eye` looking at `target`, 50° vertical field of view.
fn camera(eye: Vec3, target: Vec3, up: Vec3, aspect: f32) -> FrameCamera {
    FrameCamera::look_at(eye, target, up, 50f32.to_radians(), aspect, (0.1, 400.0))
}

fn render(scene: &Scene, set: &DecalSet, camera: &FrameCamera, size: (u32, u32)) -> Vec<u8> {
    let (width, height) = size;
    let config = RendererConfig {
        width,
        height,
        msaa: 4,
        path: RenderPath::Clustered,
        ambient: renderer::frame::Ambient::uniform(Vec3::splat(0.6)),
        ..Default::default()
    };
    gpu_test(|gpu| render_frame_with(gpu, scene, config, &[], set, camera).rgba)
}

/// Texel gap between two atlas rectangles `[left, top, width, height]` (0 when they touch).
fn gap(a: [u32; 4], b: [u32; 4]) -> u32 {
    let apart =
        |a0: u32, a1: u32, b0: u32, b1: u32| b0.saturating_sub(a1).max(a0.saturating_sub(b1));
    apart(a[0], a[0] + a[2], b[0], b[0] + b[2]).max(apart(a[1], a[1] + a[3], b[1], b[1] + b[3]))
}

#[test]
fn atlas_neighbours_never_bleed_into_a_decal_at_a_grazing_angle() {
    let red = || solid("red", 64, [255, 0, 0, 255]);
    let green = |n: usize| solid(&format!("green {n}"), 64, [0, 255, 0, 255]);
    let crowded = vec![green(0), red(), green(1), green(2), green(3)];
    // The red material's rectangle lies one double gutter from a green one: nothing but the
    // gutters keeps green out of it.
    let atlas = DecalAtlas::build(&crowded, DecalAtlasConfig::default()).expect("packs");
    let nearest = [0, 2, 3, 4]
        .iter()
        .map(|&g| gap(atlas.entries[1].texels, atlas.entries[g].texels))
        .min();
    assert_eq!(nearest, Some(2 * atlas.gutter), "{:?}", atlas.entries);
    // 120 long down the view, 8 wide, seen from 1.5 up at 10° below the horizon.
    let stretched = |material| {
        Decal::new(
            flat_box(Vec3::new(0.0, 0.0, -60.0), 8.0, 120.0, 1.0),
            material,
        )
    };
    let alone = DecalSet {
        materials: vec![red()],
        decals: vec![stretched(0)],
    };
    let among = DecalSet {
        materials: crowded,
        decals: vec![stretched(1)],
    };
    let scene = floor(200.0, Vec3::splat(0.6));
    let size = (320, 180);
    let pitch = 10f32.to_radians();
    let eye = Vec3::new(0.0, 1.5, 4.0);
    let look = eye + Vec3::new(0.0, -pitch.sin(), -pitch.cos());
    let view = camera(eye, look, Vec3::Y, 320.0 / 180.0);
    let bare = render(&scene, &DecalSet::default(), &view, size);
    let a = render(&scene, &alone, &view, size);
    let b = render(&scene, &among, &view, size);
    let reddened = bare
        .chunks(4)
        .zip(a.chunks(4))
        .filter(|(p, q)| q[0] > p[0] + 20 && q[1] + 20 < p[1])
        .count();
    assert!(
        reddened > 320 * 180 / 10,
        "the decal covers the floor: {reddened}"
    );
    let greener = a
        .chunks(4)
        .zip(b.chunks(4))
        .filter(|(p, q)| q[1] > p[1] + 1)
        .count();
    assert_eq!(greener, 0, "pixels with green bled in from a neighbour");
    let worst = largest_difference(&a, &b);
    assert!(worst <= 1, "alone vs among neighbours: {worst}");
}

/// A black and white checkerboard of one-texel squares.
fn checkerboard(side: u32) -> DecalMaterial {
    DecalMaterial {
        name: "checkerboard".into(),
        base_color: DecalImage::from_fn(side, side, |x, y| {
            let v = if (x + y) % 2 == 0 { 255 } else { 0 };
            [v, v, v, 255]
        }),
        normal: None,
        orm: None,
        emissive: None,
    }
}

#[test]
fn box_projection_gradients_blur_a_fine_pattern_seen_from_afar() {
    // 64 one-texel squares over 2 units, seen from 16 up: about 4.5 texels a pixel, so level 2
    // or so. Level 0 would show a moiré whose neighbours differ by up to the whole range.
    let (w, h) = (128, 128);
    let scene = floor(20.0, Vec3::new(0.6, 0.1, 0.1));
    let view = camera(Vec3::new(0.0, 16.0, 0.0), Vec3::ZERO, Vec3::NEG_Z, 1.0);
    let set = DecalSet {
        materials: vec![checkerboard(64)],
        decals: vec![Decal::new(flat_box(Vec3::ZERO, 2.0, 2.0, 0.5), 0)],
    };
    let image = render(&scene, &set, &view, (w, h));
    // The decal's square on screen, two pixels in from its edges.
    let clip = view.projection * view.view;
    let corner = |x: f32, z: f32| {
        let ndc = clip.project_point3(Vec3::new(x, 0.0, z)).xy();
        (
            (ndc.x + 1.0) * 0.5 * w as f32,
            (1.0 - ndc.y) * 0.5 * h as f32,
        )
    };
    let (x0, y0) = corner(-1.0, -1.0);
    let (x1, y1) = corner(1.0, 1.0);
    let xs = (x0.min(x1).ceil() as u32 + 2)..(x0.max(x1).floor() as u32 - 2);
    let ys = (y0.min(y1).ceil() as u32 + 2)..(y0.max(y1).floor() as u32 - 2);
    assert!(xs.len() >= 10 && ys.len() >= 10, "{xs:?} {ys:?}");
    let green = |x: u32, y: u32| image[((y * w + x) * 4 + 1) as usize];
    // Grey, not the floor's red: the decal is there.
    assert!(
        green(w / 2, h / 2) > green(2, 2) + 40,
        "{} {}",
        green(w / 2, h / 2),
        green(2, 2)
    );
    for y in ys {
        for x in xs.clone().skip(1) {
            let step = green(x, y).abs_diff(green(x - 1, y));
            assert!(
                step <= 4,
                "({x}, {y}): neighbours differ by {step}: aliased, not blurred"
            );
        }
    }
}
