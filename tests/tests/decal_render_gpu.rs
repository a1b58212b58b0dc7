//! Decals end to end through the renderer. Culling decals never changes the image: with seeded
//! decals (rotated, tiny, huge, overlapping, fading) and lights, every culled path equals the
//! naive image, which applies every decal at every pixel. Layers follow the sort key. Decals
//! reach blended surfaces, and never a surface outside their box (the stage's CPU ray cast says
//! which pixels show a surface inside a box). And each channel lands where an independent CPU
//! projection puts it: a decal whose base colour, normal and occlusion-roughness-metalness images
//! are three different asymmetric letters (`tests::decal_letters`), on the naive, clustered and
//! TBDR paths; every pixel is checked but a band about a pixel and half a texel wide along each
//! edge. A mirrored (u → 1 − u) or rotated (u, v swapped) projection and normal and ORM maps
//! read from each other's textures each failed it (mutations in `shared::decal_apply`). A set
//! edited over the same materials keeps the atlas and draws as a fresh one (`edits`).

use glam::{Mat4, Quat, Vec3};
use renderer::decals::{Decal, DecalSet, OrientedBox, box_on_surface, procedural};
use renderer::demo::procedural_lights;
use renderer::demo::scatter_decals;
use renderer::frame::default_camera;
use renderer::frame::{FrameCamera, RenderPath, RendererConfig};
use renderer::scene::{Scene, SceneLight};
use tests::decal_stage::{self, HEIGHT, Reach, WIDTH, flat_box, solid};
use tests::frames::{committed_scene, largest_difference, render_frame_with};
use tests::gpu::gpu_test;

#[path = "decal_render_gpu/edits.rs"]
mod edits;

const CULLED: [RenderPath; 5] = [
    RenderPath::NaivePrez,
    RenderPath::Tiled,
    RenderPath::Depth25,
    RenderPath::Clustered,
    RenderPath::Visibility,
];

/// The visibility path may differ from naive by more than one step at one pixel in this many
/// (its points rebuilt from the triangle's plane, not interpolated)...
const VISIBILITY_EXCEPTIONS: usize = 500;
/// ...and there by at most this much.
const VISIBILITY_WORST: u8 = 24;

/// Pixels whose colour differs between two RGBA8 images by more than `by` in some channel.
fn changed_pixels(a: &[u8], b: &[u8], by: u8) -> usize {
    a.chunks(4)
        .zip(b.chunks(4))
        .filter(|(p, q)| p.iter().zip(*q).any(|(x, y)| x.abs_diff(*y) > by))
        .count()
}

/// A surface point and its normal: the centre and +Z of a decal placed by `scatter`.
fn anchor(decal: &Decal) -> (Vec3, Vec3) {
    let m = decal.world_from_box;
    (m.w_axis.truncate(), m.z_axis.truncate().normalize())
}

/// 48 decals scattered over `scene` (seeded, rolled, keys 0–3), then the hard cases: one under
/// a pixel, one holding most of the scene (rotated, half blended), one tilted 40° off its
/// surface (the angle fade part way), a stack of four on one point in shuffled key order, and
/// distance fades that end inside the view.
fn decal_set(scene: &Scene, seed: u64) -> DecalSet {
    let materials = procedural::materials();
    let mut decals = scatter_decals(scene, 48, materials.len(), seed);
    let diagonal = (scene.bounds.max - scene.bounds.min).length();
    let ((a, a_normal), (b, b_normal)) = (anchor(&decals[0]), anchor(&decals[1]));
    decals.push(Decal::new(
        box_on_surface(a, a_normal, 0.7, Vec3::splat(diagonal * 0.004)),
        0,
    ));
    let skew = Quat::from_axis_angle(Vec3::new(1.0, 0.4, 0.2).normalize(), 35f32.to_radians());
    let mut huge = Decal::new(
        Mat4::from_scale_rotation_translation(
            Vec3::splat(diagonal * 0.6),
            skew,
            scene.bounds.center(),
        ),
        1,
    );
    huge.blend = 0.5;
    decals.push(huge);
    let across = b_normal.any_orthonormal_vector();
    let tilted = Quat::from_axis_angle(across, 40f32.to_radians()) * b_normal;
    decals.push(Decal::new(
        box_on_surface(b, tilted, 0.0, Vec3::splat(diagonal * 0.08)),
        2,
    ));
    for (k, key) in [3, 1, 2, 0].into_iter().enumerate() {
        let side = diagonal * (0.05 + 0.01 * k as f32);
        let mut d = Decal::new(
            box_on_surface(
                a,
                a_normal,
                k as f32,
                Vec3::new(side, side * 0.7, side * 0.5),
            ),
            k % materials.len(),
        );
        d.sort_key = key;
        decals.push(d);
    }
    for d in decals.iter_mut().step_by(5) {
        d.distance_fade = [diagonal * 0.8, diagonal * 1.4];
    }
    DecalSet { materials, decals }
}

/// Renders `scene` with `lights` and `decals` on every path, and checks each culled image
/// against the naive one and the decals against an image without them.
fn assert_culled_equals_naive(
    scene: &Scene,
    lights: &[SceneLight],
    decals: &DecalSet,
    (width, height, msaa): (u32, u32, u32),
    what: &str,
) {
    let camera = default_camera(scene, width as f32 / height as f32);
    let config = |path| RendererConfig {
        width,
        height,
        msaa,
        path,
        tile: 16,
        // Ambient light, so that decals show in places the seeded lights leave dark.
        ambient: renderer::frame::Ambient::uniform(Vec3::splat(0.3)),
        ..Default::default()
    };
    gpu_test(|gpu| {
        let render = |path, decals: &DecalSet| {
            let frame = render_frame_with(gpu, scene, config(path), lights, decals, &camera);
            let dropped = frame.culling.map_or(0, |c| c.dropped);
            assert_eq!(
                dropped, 0,
                "{what} {path:?}: the comparison needs whole lists"
            );
            frame.rgba
        };
        let naive = render(RenderPath::Naive, decals);
        let bare = render(RenderPath::Naive, &DecalSet::default());
        let changed = changed_pixels(&naive, &bare, 8);
        let pixels = (width * height) as usize;
        assert!(
            changed > pixels / 20,
            "{what}: the decals must change the image visibly ({changed} of {pixels} pixels)"
        );
        for path in CULLED {
            let culled = render(path, decals);
            // One 8-bit step: culled paths sum the same lights in another order (f32 addition is
            // not associative); decals are applied in the same layer order on every path.
            let worst = largest_difference(&naive, &culled);
            if path == RenderPath::Visibility {
                // It rebuilds each point from its triangle's plane rather than interpolating it:
                // measured, 0 to 12 pixels per frame differ by more than a step (at most 10).
                let off = changed_pixels(&naive, &culled, 1);
                eprintln!(
                    "{what} {path:?} at MSAA {msaa}: {off} pixels off by more than 1, worst {worst}"
                );
                assert!(
                    off <= pixels / VISIBILITY_EXCEPTIONS && worst <= VISIBILITY_WORST,
                    "{what} {path:?} at MSAA {msaa}: {off} pixels differ from naive by more \
                     than 1 (at most {}), the worst by {worst} (at most {VISIBILITY_WORST})",
                    pixels / VISIBILITY_EXCEPTIONS
                );
                continue;
            }
            assert!(
                worst <= 1,
                "{what} {path:?} at MSAA {msaa}: differs from naive by {worst}"
            );
        }
    });
}

#[test]
fn culled_paths_with_decals_equal_naive_on_the_committed_scene() {
    let scene = committed_scene();
    let size = (scene.bounds.max - scene.bounds.min).length();
    let lights = procedural_lights(scene.bounds, 64, 5, size * 0.05, size * 0.3);
    for msaa in [1, 4] {
        for seed in [1, 2] {
            let what = format!("committed scene, seed {seed}");
            let decals = decal_set(&scene, seed);
            assert_culled_equals_naive(&scene, &lights, &decals, (128, 96, msaa), &what);
        }
    }
}

#[test]
fn culled_paths_with_decals_equal_naive_on_the_courtyard() {
    use renderer::scene::procedural::{COURTYARD_LIGHT_REGION, courtyard};
    let scene = courtyard();
    let lights = procedural_lights(COURTYARD_LIGHT_REGION, 256, 7, 0.8, 2.6);
    let decals = decal_set(&scene, 3);
    assert_culled_equals_naive(&scene, &lights, &decals, (128, 72, 4), "courtyard");
}

/// Renders the stage with `decals` (materials red, green) on `path` at MSAA `msaa`.
fn stage_frame(set: &DecalSet, path: RenderPath, msaa: u32) -> Vec<u8> {
    let config = RendererConfig {
        width: WIDTH,
        height: HEIGHT,
        msaa,
        path,
        tile: 16,
        ambient: renderer::frame::Ambient::uniform(Vec3::splat(0.25)),
        ..Default::default()
    };
    let scene = decal_stage::scene();
    gpu_test(|gpu| {
        let frame = render_frame_with(
            gpu,
            &scene,
            config,
            &decal_stage::lights(),
            set,
            &decal_stage::camera(),
        );
        assert_eq!(frame.culling.map_or(0, |c| c.dropped), 0);
        frame.rgba
    })
}

fn red_and_green() -> Vec<renderer::decals::DecalMaterial> {
    vec![
        solid("red", 16, [255, 0, 0, 255]),
        solid("green", 16, [0, 255, 0, 255]),
    ]
}

fn bounds(decal: &Decal) -> OrientedBox {
    decal.bounds().expect("a valid box")
}

fn pixel(rgba: &[u8], x: u32, y: u32) -> [u8; 3] {
    let i = ((y * WIDTH + x) * 4) as usize;
    [rgba[i], rgba[i + 1], rgba[i + 2]]
}

#[test]
fn layers_follow_the_sort_key_and_swapping_two_keys_swaps_the_overlap() {
    let camera: FrameCamera = decal_stage::camera();
    let red = Decal::new(flat_box(Vec3::new(-0.4, 0.0, 0.0), 2.0, 2.0, 0.5), 0);
    let green = Decal::new(flat_box(Vec3::new(0.4, 0.0, 0.0), 2.0, 2.0, 0.5), 1);
    // Pixels showing floor inside both boxes.
    let overlap: Vec<(u32, u32)> = (0..HEIGHT)
        .flat_map(|y| (0..WIDTH).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            [&red, &green].iter().all(|d| {
                decal_stage::reach(&camera, &[bounds(d)], x, y) == Reach::Inside { box_index: 0 }
            })
        })
        .collect();
    assert!(overlap.len() > 100, "overlap pixels: {}", overlap.len());
    // (red key, green key, which wins): equal keys keep the set's order, so green (second) wins.
    for (red_key, green_key, red_wins) in [(0, 1, false), (1, 0, true), (2, 2, false)] {
        let set = DecalSet {
            materials: red_and_green(),
            decals: vec![
                Decal {
                    sort_key: red_key,
                    ..red
                },
                Decal {
                    sort_key: green_key,
                    ..green
                },
            ],
        };
        let naive = stage_frame(&set, RenderPath::Naive, 4);
        for &(x, y) in &overlap {
            let [r, g, _] = pixel(&naive, x, y);
            let shown = if red_wins { r > g + 40 } else { g > r + 40 };
            assert!(
                shown,
                "keys red {red_key}, green {green_key}: ({x}, {y}) is {:?}",
                [r, g]
            );
        }
        for path in [RenderPath::Tiled, RenderPath::Clustered] {
            let worst = largest_difference(&naive, &stage_frame(&set, path, 4));
            assert!(worst <= 1, "{path:?}: differs from naive by {worst}");
        }
    }
}

#[test]
fn decals_reach_blended_surfaces_and_never_leak_outside_their_boxes() {
    let camera = decal_stage::camera();
    // On the floor, under the shelf's edge (the shelf at y = 1 is above the box: outside it),
    // and around the blended pane at y = 0.5 only (the floor under the pane is outside it).
    let on_floor = Decal::new(flat_box(Vec3::ZERO, 2.0, 2.0, 0.5), 0);
    let on_pane = Decal::new(flat_box(Vec3::new(-2.6, 0.5, 0.0), 2.0, 2.0, 0.2), 1);
    let set = DecalSet {
        materials: red_and_green(),
        decals: vec![on_floor, on_pane],
    };
    let boxes = [bounds(&on_floor), bounds(&on_pane)];
    let reach: Vec<(u32, u32, Reach)> = (0..HEIGHT)
        .flat_map(|y| (0..WIDTH).map(move |x| (x, y)))
        .map(|(x, y)| (x, y, decal_stage::reach(&camera, &boxes, x, y)))
        .collect();
    let inside = |k| {
        reach
            .iter()
            .filter(|p| p.2 == Reach::Inside { box_index: k })
            .count()
    };
    assert!(
        inside(0) > 100 && inside(1) > 100,
        "{} {}",
        inside(0),
        inside(1)
    );
    // Pixels where the floor below lies in the box but the shelf above it is what shows.
    let shelf_over_box = reach
        .iter()
        .filter(|&&(x, y, r)| {
            let ray = decal_stage::ray(&camera, x as f32 + 0.5, y as f32 + 0.5);
            let floor = decal_stage::SLABS[2].hit(ray);
            r == Reach::Outside && floor.is_some_and(|p| boxes[0].contains(p))
        })
        .count();
    assert!(shelf_over_box > 20, "shelf over the box: {shelf_over_box}");
    for (path, msaa) in [
        (RenderPath::Naive, 1),
        (RenderPath::Naive, 4),
        (RenderPath::Tiled, 4),
        (RenderPath::Clustered, 4),
    ] {
        let bare = stage_frame(&DecalSet::default(), path, msaa);
        let with = stage_frame(&set, path, msaa);
        for &(x, y, r) in &reach {
            let (a, b) = (pixel(&bare, x, y), pixel(&with, x, y));
            let moved = a.iter().zip(b).map(|(p, q)| p.abs_diff(q)).max();
            match r {
                Reach::Outside => assert_eq!(
                    a, b,
                    "{path:?} MSAA {msaa}: ({x}, {y}) shows no surface in a box, yet changed"
                ),
                Reach::Inside { box_index } => assert!(
                    moved > Some(24),
                    "{path:?} MSAA {msaa}: ({x}, {y}) lies in box {box_index}: {a:?} -> {b:?}"
                ),
                Reach::Edge => {}
            }
        }
    }
}

/// The letter frames of one path: with no decal, then with the letter decal (every letter, and
/// each of the base-colour and occlusion-roughness-metalness letters erased) lit by ambient
/// light only, then (every letter, the normal letter erased) with a grazing light added.
fn letter_frames(path: RenderPath, msaa: u32) -> [Vec<u8>; 6] {
    use renderer::decals::Channel;
    use tests::decal_letters::{self as letters, HEIGHT, WIDTH};
    let config = RendererConfig {
        width: WIDTH,
        height: HEIGHT,
        msaa,
        path,
        tile: 16,
        ambient: renderer::frame::Ambient::uniform(Vec3::splat(0.5)),
        ..Default::default()
    };
    let scene = letters::scene();
    let camera = letters::camera();
    let set = |erased| DecalSet {
        materials: vec![letters::material(erased)],
        decals: vec![letters::decal()],
    };
    let dark: &[SceneLight] = &[];
    let lit = [letters::grazing_light()];
    let frames = [
        (dark, DecalSet::default()),
        (dark, set(None)),
        (dark, set(Some(Channel::BaseColor))),
        (dark, set(Some(Channel::Orm))),
        (&lit[..], set(None)),
        (&lit[..], set(Some(Channel::Normal))),
    ];
    gpu_test(|gpu| {
        frames.map(|(lights, decals)| {
            let frame = render_frame_with(gpu, &scene, config, lights, &decals, &camera);
            assert_eq!(frame.culling.map_or(0, |c| c.dropped), 0);
            frame.rgba
        })
    })
}

fn luma(p: [u8; 3]) -> f32 {
    0.2126 * f32::from(p[0]) + 0.7152 * f32::from(p[1]) + 0.0722 * f32::from(p[2])
}

#[test]
fn each_channel_of_a_lettered_decal_lands_where_the_cpu_projection_puts_its_letter() {
    use tests::decal_letters::{self as letters, Coverage, F, FOUR, Glyph, HEIGHT, R, WIDTH};
    // (what, glyph (None: the box), frames compared (with, without), the change ink must show).
    type Change = fn([u8; 3], [u8; 3]) -> bool;
    type Check = (&'static str, Option<&'static Glyph>, (usize, usize), Change);
    let checks: [Check; 4] = [
        // The decal (blue paper, red ink) replaces the grey floor inside the box.
        ("box", None, (1, 0), |a, b| {
            a.iter().zip(b).any(|(x, y)| x.abs_diff(y) >= 24)
        }),
        // Red ink on blue paper, under ambient light.
        ("base colour F", Some(&F), (1, 2), |a, b| {
            a[0] >= b[0] + 24 && a[2] + 24 <= b[2]
        }),
        // Occlusion 0.35: the ambient term darker in every channel.
        ("occlusion 4", Some(&FOUR), (1, 3), |a, b| {
            a.iter().zip(b).all(|(x, y)| *x <= y) && a.iter().zip(b).any(|(x, y)| x + 24 <= y)
        }),
        // Normals tilted towards a grazing light: brighter.
        ("normal R", Some(&R), (4, 5), |a, b| {
            luma(a) >= luma(b) + 20.0
        }),
    ];
    let coverage: Vec<Vec<Coverage>> = checks
        .iter()
        .map(|&(_, glyph, _, _)| {
            (0..HEIGHT)
                .flat_map(|y| (0..WIDTH).map(move |x| letters::coverage(glyph, x, y)))
                .collect()
        })
        .collect();
    for (path, msaa) in [
        (RenderPath::Naive, 1),
        (RenderPath::Clustered, 4),
        (RenderPath::Tbdr, 4),
    ] {
        let frames = letter_frames(path, msaa);
        let at = |frame: usize, i: usize| {
            let p = &frames[frame][i * 4..i * 4 + 3];
            [p[0], p[1], p[2]]
        };
        for ((what, _, (with, without), changed), cover) in checks.iter().zip(&coverage) {
            let (mut ink, mut clear) = (0, 0);
            for (i, c) in cover.iter().enumerate() {
                let (x, y) = (i as u32 % WIDTH, i as u32 / WIDTH);
                let (a, b) = (at(*with, i), at(*without, i));
                match c {
                    Coverage::Ink => {
                        ink += 1;
                        assert!(
                            changed(a, b),
                            "{path:?}: {what}: ({x}, {y}) lies on ink, yet {b:?} -> {a:?}"
                        );
                    }
                    Coverage::Clear => {
                        clear += 1;
                        assert_eq!(
                            a, b,
                            "{path:?}: {what}: ({x}, {y}) lies off the letter, yet changed"
                        );
                    }
                    Coverage::Band => {}
                }
            }
            eprintln!("{path:?} {what}: {ink} ink and {clear} clear pixels checked");
            assert!(ink >= 400, "{what}: only {ink} ink pixels");
        }
    }
}
