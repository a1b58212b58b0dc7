//! Negative scales (glTF 2.0, "Instantiation": a node whose global transform has a negative
//! determinant winds its triangles clockwise). Two checks:
//! * a mirrored node against its unmirrored twin built in code: a single-sided, textured,
//!   normal-mapped box at `A` and its mirror image at `Mx · A` (`Mx` flips X), seen by a camera
//!   and a light on the mirror plane, must render as the mirror image of each other: the frame
//!   equals its own left-right flip, on every path that draws meshes (pre-Z, forward's three
//!   list kinds, the G-buffer of TBDR and deferred), placed by the file and moved at run time;
//!   two short-range lights just in front of the boxes make a pre-Z pass with the wrong winding
//!   show too (the culled paths would drop the mirrored box's light);
//! * Khronos's `NegativeScaleTest`, where the README says what must show: green checks, and no
//!   red crosses (the back faces of the mirrored row, which show when culling keeps the wrong
//!   winding), and its double-sided white spheres lit alike, mirrored or not (a mirrored sphere
//!   whose front faces counted as back faces would be lit with flipped normals).

use glam::{Mat4, Vec3, Vec4};
use renderer::frame::{FrameCamera, RenderPath, Renderer, RendererConfig};
use renderer::scene::TextureRef;
use renderer::scene::procedural::SceneBuilder;
use renderer::scene::{Aabb, AlphaMode, Image, Instance, LightKind, Material, Scene, SceneLight};
use tests::frames::{render_frame_from, render_one_frame};
use tests::gpu::gpu_test;

use super::sample;

const W: u32 = 128;
const H: u32 = 72;
/// Every path that draws the scene's meshes its own way: no pre-pass, pre-Z with forward's
/// naive, tiled and clustered lists, and the G-buffer of the two deferred paths.
const PATHS: [RenderPath; 6] = [
    RenderPath::Naive,
    RenderPath::NaivePrez,
    RenderPath::Tiled,
    RenderPath::Clustered,
    RenderPath::Tbdr,
    RenderPath::Deferred,
];
/// How far a pixel's channel may lie outside the range its mirror pixel's 3×3 neighbourhood
/// spans (8-bit, sRGB). The rasteriser's tie rule (top-left) is not mirror-symmetric, so an edge
/// (silhouette, face or texel edge) may land a pixel over in the mirror image; the neighbourhood
/// covers that, the tolerance the rounding of mirrored arithmetic.
const TOLERANCE: u8 = 4;
/// Pixels allowed beyond that, as a fraction of the frame.
const EDGE_ALLOWANCE: f64 = 0.002;

/// An RGBA8 image of `side`² texels from `texel(x, y)`.
fn image(side: u32, texel: impl Fn(u32, u32) -> [u8; 4]) -> Image {
    let rgba8 = (0..side * side)
        .flat_map(|i| texel(i % side, i / side))
        .collect();
    Image {
        width: side,
        height: side,
        rgba8,
    }
}

/// `Mx`: the mirror across the plane x = 0, where the camera and the light stand.
fn mirror_x() -> Mat4 {
    Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0))
}

/// The unmirrored box's placement: right of the mirror plane, turned so three faces show.
fn twin_placement() -> Mat4 {
    Mat4::from_translation(Vec3::new(1.3, 0.0, 0.0))
        * Mat4::from_rotation_x(0.45)
        * Mat4::from_rotation_y(0.6)
        * Mat4::from_rotation_z(0.2)
}

/// A unit box, single-sided, whose base colour (four unequal quadrants) and normal map (normals
/// tilted along both tangent axes: a flipped bitangent lights it differently) tell a mirror
/// image from a rotated one; instance 0 at [`twin_placement`], instance 1 at `second`.
fn twins(second: Mat4) -> Scene {
    let mut b = SceneBuilder::new();
    let colour = b.image(image(8, |x, y| match (x < 3, y < 5) {
        (true, true) => [220, 40, 40, 255],
        (false, true) => [40, 200, 60, 255],
        (true, false) => [50, 70, 230, 255],
        (false, false) => [235, 235, 235, 255],
    }));
    // Tangent-space normal (0.35, 0.5, 0.79), as a normal texture stores it.
    let normal = b.image(image(1, |_, _| [172, 191, 228, 255]));
    let material = b.add_material(Material {
        name: "asymmetric".into(),
        base_color: Vec4::ONE,
        base_color_texture: Some(TextureRef::new(colour)),
        normal_texture: Some(TextureRef::new(normal)),
        metallic: 0.0,
        roughness: 0.45,
        alpha_mode: AlphaMode::Opaque,
        double_sided: false,
        ..Material::gltf_default()
    });
    b.cuboid(Vec3::splat(-0.5), Vec3::splat(0.5), material);
    let mut scene = b.build();
    scene.instances[0].world_from_mesh = twin_placement();
    scene.instances.push(Instance {
        mesh: 0,
        world_from_mesh: second,
    });
    scene.bounds = Aabb {
        min: Vec3::splat(-2.5),
        max: Vec3::splat(2.5),
    };
    scene
}

/// A light and a camera on the mirror plane: above and in front of the boxes.
fn symmetric_light() -> SceneLight {
    SceneLight {
        kind: LightKind::Point,
        position: Vec3::new(0.0, 2.5, 3.0),
        direction: Vec3::NEG_Z,
        color: Vec3::ONE,
        intensity: 40.0,
        range: None,
        casts_shadow: false,
    }
}

/// Two small lights in front of the boxes' camera-facing faces, mirror images of each other,
/// whose range (0.6) reaches those faces and not the faces behind: a pre-Z pass that kept a
/// mirrored box's back faces would push its tiles' depth bounds behind the light, and the
/// culled paths would drop it there (naive forward, which culls nothing, would not see it).
fn front_lights() -> [SceneLight; 2] {
    [1.0, -1.0].map(|side| SceneLight {
        kind: LightKind::Point,
        position: Vec3::new(1.3 * side, 0.0, 1.1),
        direction: Vec3::NEG_Z,
        color: Vec3::new(1.0, 0.8, 0.5),
        intensity: 1.5,
        range: Some(0.6),
        casts_shadow: false,
    })
}

fn symmetric_camera() -> FrameCamera {
    FrameCamera::look_at(
        Vec3::new(0.0, 0.4, 5.0),
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::Y,
        40f32.to_radians(),
        W as f32 / H as f32,
        (0.5, 20.0),
    )
}

fn config(path: RenderPath) -> RendererConfig {
    RendererConfig {
        width: W,
        height: H,
        msaa: 4,
        path,
        ..Default::default()
    }
}

/// How far `rgba` (W × H) is from its own left-right flip: the pixels beyond [`TOLERANCE`] of
/// their mirror pixel's neighbourhood, the largest such excess, and how many pixels are not
/// background on each half (both boxes must show).
fn asymmetry(rgba: &[u8]) -> (usize, u8, usize, usize) {
    let px = |x: u32, y: u32| &rgba[((y * W + x) * 4) as usize..][..3];
    let (mut beyond, mut largest, mut left, mut right) = (0, 0, 0, 0);
    for y in 0..H {
        for x in 0..W {
            let (mx, mut d) = (W - 1 - x, 0u8);
            for c in 0..3 {
                let around = (y.saturating_sub(1)..=(y + 1).min(H - 1)).flat_map(|ny| {
                    (mx.saturating_sub(1)..=(mx + 1).min(W - 1)).map(move |nx| (nx, ny))
                });
                let values: Vec<u8> = around.map(|(nx, ny)| px(nx, ny)[c]).collect();
                let (lo, hi) = (values.iter().min(), values.iter().max());
                let v = px(x, y)[c];
                if let (Some(&lo), Some(&hi)) = (lo, hi) {
                    d = d.max(lo.saturating_sub(v)).max(v.saturating_sub(hi));
                }
            }
            beyond += usize::from(d > TOLERANCE);
            largest = largest.max(d);
            if px(x, y).iter().any(|&c| c > 8) {
                if x < W / 2 { left += 1 } else { right += 1 }
            }
        }
    }
    (beyond, largest, left, right)
}

fn assert_mirror_image(rgba: &[u8], what: &str) {
    let _ = image::save_buffer(
        std::env::temp_dir().join(format!("negative_scale_{}.png", what.replace(' ', "_"))),
        rgba,
        W,
        H,
        image::ExtendedColorType::Rgba8,
    );
    let (beyond, largest, left, right) = asymmetry(rgba);
    let allowed = (f64::from(W * H) * EDGE_ALLOWANCE) as usize;
    eprintln!(
        "{what}: {beyond} pixels beyond {TOLERANCE} (allowed {allowed}), largest {largest}; covered {left} | {right}"
    );
    assert!(
        left > 300 && right > 300,
        "{what}: both boxes must show (covered pixels: left {left}, right {right})"
    );
    assert!(
        beyond <= allowed,
        "{what}: the mirrored box is not the mirror image of its twin: {beyond} pixels differ from \
         their mirror pixel by more than {TOLERANCE} (largest {largest}, allowed {allowed})"
    );
}

#[test]
fn a_mirrored_node_renders_as_the_mirror_image_of_its_twin_on_every_path() {
    let scene = twins(mirror_x() * twin_placement());
    assert!(scene.instances[1].world_from_mesh.determinant() < 0.0);
    gpu_test(|gpu| {
        for path in PATHS {
            let [right, left] = front_lights();
            let frame = render_frame_from(
                gpu,
                &scene,
                config(path),
                &[symmetric_light(), right, left],
                &symmetric_camera(),
            );
            assert_mirror_image(&frame.rgba, path.name());
        }
    });
}

#[test]
fn an_instance_moved_into_a_mirror_renders_mirrored_and_back() {
    // Placed unmirrored (a half turn about Y: the same side of the plane, not a mirror image),
    // then moved at run time to the mirror placement, then back.
    let turned = Mat4::from_rotation_y(std::f32::consts::PI) * twin_placement();
    let scene = twins(turned);
    gpu_test(|gpu| {
        for path in [RenderPath::Tiled, RenderPath::Tbdr] {
            let mut renderer = Renderer::new(gpu, config(path)).expect("renderer");
            renderer.prepare_scene(&scene).expect("scene fits");
            renderer
                .set_lights(&[symmetric_light()])
                .expect("lights fit");
            let camera = symmetric_camera();
            let unmirrored = render_one_frame(gpu, &mut renderer, &camera).rgba;
            let twin = renderer.scene_instance(1).expect("instance 1");
            renderer
                .set_instance_transform(twin, mirror_x() * twin_placement())
                .expect("instance 1");
            let mirrored = render_one_frame(gpu, &mut renderer, &camera).rgba;
            assert_mirror_image(&mirrored, &format!("{} moved into the mirror", path.name()));
            renderer
                .set_instance_transform(twin, turned)
                .expect("instance 1");
            let back = render_one_frame(gpu, &mut renderer, &camera).rgba;
            let (beyond, ..) = asymmetry(&back);
            assert!(
                back == unmirrored && beyond > (f64::from(W * H) * EDGE_ALLOWANCE) as usize,
                "{}: moved back, the frame must be the unmirrored one again",
                path.name()
            );
        }
    });
}

/// Sample colours: the crosses' red and the checks' green (8-bit sRGB, lit).
fn is_red(p: &[u8]) -> bool {
    p[0] > 120 && p[1] < 70 && p[2] < 70
}
fn is_green(p: &[u8]) -> bool {
    p[1] > 120 && p[0] < 70 && p[2] < 70
}

#[test]
fn negative_scale_test_shows_checks_no_crosses_and_its_spheres_lit_alike() {
    let scene = sample("NegativeScaleTest/NegativeScaleTest.glb");
    let (w, h) = (320, 240);
    let camera = FrameCamera::look_at(
        Vec3::new(0.0, 0.0, 14.0),
        Vec3::new(0.0, -0.3, 0.0),
        Vec3::Y,
        40f32.to_radians(),
        w as f32 / h as f32,
        (0.5, 50.0),
    );
    // Light from over the camera's shoulder; the file has none.
    let light = SceneLight {
        kind: LightKind::Directional,
        position: Vec3::ZERO,
        direction: Vec3::new(-0.3, -0.3, -1.0).normalize(),
        color: Vec3::ONE,
        intensity: 3.0,
        range: None,
        casts_shadow: false,
    };
    // The pixel where world point `p` projects.
    let pixel = |p: Vec3| {
        let clip = camera.projection * camera.view * p.extend(1.0);
        let ndc = clip.truncate() / clip.w;
        let x = ((ndc.x * 0.5 + 0.5) * w as f32) as u32;
        let y = ((0.5 - ndc.y * 0.5) * h as f32) as u32;
        (x, y)
    };
    gpu_test(|gpu| {
        for path in [RenderPath::Tiled, RenderPath::Deferred] {
            let config = RendererConfig {
                width: w,
                height: h,
                msaa: 4,
                path,
                ..Default::default()
            };
            let frame = render_frame_from(gpu, &scene, config, &[light], &camera);
            if path == RenderPath::Tiled {
                let _ = image::save_buffer(
                    std::env::temp_dir().join("negative_scale_test.png"),
                    &frame.rgba,
                    w,
                    h,
                    image::ExtendedColorType::Rgba8,
                );
            }
            let pixels: Vec<&[u8]> = frame.rgba.chunks_exact(4).collect();
            let red = pixels.iter().filter(|p| is_red(p)).count();
            let green = pixels.iter().filter(|p| is_green(p)).count();
            eprintln!("{}: red {red}, green {green}", path.name());
            // The white spheres, at (1, -1, 0) and, mirrored, (3, -1, 0): lit alike.
            let mean = |centre: Vec3| {
                let (cx, cy) = pixel(centre);
                let mut sum = 0.0;
                for y in cy - 2..=cy + 2 {
                    for x in cx - 2..=cx + 2 {
                        let p = pixels[(y * w + x) as usize];
                        sum += f64::from(p[0]) + f64::from(p[1]) + f64::from(p[2]);
                    }
                }
                sum / 75.0
            };
            let (plain, mirrored) = (
                mean(Vec3::new(1.0, -1.0, 0.0)),
                mean(Vec3::new(3.0, -1.0, 0.0)),
            );
            eprintln!(
                "{}: white spheres {plain:.1} and {mirrored:.1}",
                path.name()
            );
            assert!(
                red < 10 && green > 150,
                "{}: NegativeScaleTest must show green checks and no red crosses: {red} red \
                 pixels, {green} green",
                path.name()
            );
            assert!(
                plain > 60.0 && (plain - mirrored).abs() < 0.15 * plain,
                "{}: the mirrored white sphere must be lit like the plain one: {mirrored:.1} \
                 against {plain:.1}",
                path.name()
            );
        }
    });
}
