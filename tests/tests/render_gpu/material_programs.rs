//! Materials written in the shader DSL (`tests::materials`, as an engine writes them) drawn by
//! the renderer: what their surface function returns is what the frame shows, parameters
//! reach each material's own record, every path equals naive with them, and bad programs and
//! bad uses are typed errors.

use glam::{Vec3, Vec4};
use renderer::demo::procedural_lights;
use renderer::frame::InputError;
use renderer::frame::{Ambient, FrameCamera, RenderError, RenderPath, Renderer, RendererConfig};
use renderer::materials::{MaterialError, MaterialProgram};
use renderer::scene::procedural::{COURTYARD_LIGHT_REGION, SceneBuilder, courtyard};
use renderer::scene::{AlphaMode, CustomShading, Material, Scene};
use tests::frames::{largest_difference, render_one_frame};
use tests::gpu::gpu_test;
use tests::image_compare::{pixel_differences, stats};
use tests::materials::{checker, normal_colour};

const WIDTH: u32 = 128;
const HEIGHT: u32 = 64;

fn programs() -> [MaterialProgram; 2] {
    [
        MaterialProgram::new(&checker::MODULE).expect("a #[material] module is a program"),
        MaterialProgram::new(&normal_colour::MODULE).expect("a #[material] module is a program"),
    ]
}

fn checker_params(first: Vec3, second: Vec3, cell: f32, glow: f32) -> checker::Checker {
    checker::Checker::new(
        first.extend(1.0),
        second.extend(1.0),
        cell,
        glow,
        glam::Vec2::ZERO,
    )
}

/// A renderer of `config` with both test programs registered and `scene` prepared.
fn renderer(gpu: &renderer::GpuContext, config: RendererConfig, scene: &Scene) -> Renderer {
    let mut r = Renderer::new(gpu, config).expect("renderer");
    for p in programs() {
        r.register_material(p).expect("the program registers");
    }
    r.prepare_scene(scene).expect("the scene fits");
    r
}

/// Two floor slabs side by side, x < 0 and x > 0, each with its own checker material (red and
/// blue; green and blue cells of 0.5 m), glowing and unlit.
fn slabs() -> Scene {
    let mut b = SceneBuilder::new();
    let mut custom = |name: &str, first: Vec3| {
        b.add_material(Material {
            name: name.into(),
            custom: Some(CustomShading::new(
                "checker",
                &checker_params(first, Vec3::Z, 0.5, 1.0),
            )),
            ..Material::gltf_default()
        })
    };
    let (left, right) = (custom("red", Vec3::X), custom("green", Vec3::Y));
    b.cuboid(Vec3::new(-4.0, -0.1, -2.0), Vec3::new(0.0, 0.0, 2.0), left);
    b.cuboid(Vec3::new(0.0, -0.1, -2.0), Vec3::new(4.0, 0.0, 2.0), right);
    b.build()
}

/// Looking straight down at the slabs, 8 × 4 m in view.
fn top_camera() -> FrameCamera {
    let view =
        glam::camera::rh::view::look_at_mat4(Vec3::new(0.0, 5.0, 0.0), Vec3::ZERO, Vec3::NEG_Z);
    FrameCamera::orthographic(view.inverse(), (4.0, 2.0), (0.1, 20.0))
}

/// The colour the checker material shows at world `(x, z)` (CPU, from the parameters above),
/// or `None` within `margin` of a cell's or a slab's edge.
fn expected_cell(x: f32, z: f32, margin: f32) -> Option<Vec3> {
    let near_edge = |v: f32| (v / 0.5 - (v / 0.5).round()).abs() * 0.5 < margin;
    if near_edge(x) || near_edge(z) || x.abs() > 3.9 || z.abs() > 1.9 {
        return None;
    }
    let odd = ((x / 0.5).floor() as i32 + (z / 0.5).floor() as i32).rem_euclid(2) == 1;
    Some(match (odd, x < 0.0) {
        (true, _) => Vec3::Z,
        (false, true) => Vec3::X,
        (false, false) => Vec3::Y,
    })
}

#[test]
fn a_material_program_shows_what_its_surface_returns_with_each_materials_parameters() {
    let scene = slabs();
    let camera = top_camera();
    let inverse = (camera.projection * camera.view).inverse();
    gpu_test(|gpu| {
        for path in [RenderPath::Naive, RenderPath::Clustered, RenderPath::Tbdr] {
            let config = RendererConfig {
                width: WIDTH,
                height: HEIGHT,
                path,
                msaa: 1,
                ambient: Ambient {
                    sky: Vec3::ZERO,
                    ground: Vec3::ZERO,
                },
                ..Default::default()
            };
            let mut r = renderer(gpu, config, &scene);
            r.set_lights(&[]).expect("no lights");
            let frame = render_one_frame(gpu, &mut r, &camera);
            let mut checked = [0usize; 3];
            for y in 0..HEIGHT {
                for x in 0..WIDTH {
                    let ndc = Vec4::new(
                        2.0 * (x as f32 + 0.5) / WIDTH as f32 - 1.0,
                        1.0 - 2.0 * (y as f32 + 0.5) / HEIGHT as f32,
                        0.5,
                        1.0,
                    );
                    let world = inverse * ndc;
                    let world = world.truncate() / world.w;
                    // One pixel is 1/16 m: stay a pixel and a half off every edge.
                    let Some(want) = expected_cell(world.x, world.z, 0.1) else {
                        continue;
                    };
                    let i = ((y * WIDTH + x) * 4) as usize;
                    let got = &frame.rgba[i..i + 3];
                    let lit = want.to_array().map(|c| c > 0.5);
                    for (channel, (&value, on)) in got.iter().zip(lit).enumerate() {
                        assert!(
                            if on { value > 150 } else { value < 8 },
                            "{path:?}: pixel ({x}, {y}) at world ({:.2}, {:.2}) is {got:?}, \
                             the checker says {want} (channel {channel})",
                            world.x,
                            world.z
                        );
                    }
                    checked[lit.iter().position(|&on| on).unwrap_or(0)] += 1;
                }
            }
            assert!(
                checked.iter().all(|&n| n > 300),
                "{path:?}: every colour is checked on many pixels ({checked:?})"
            );
        }
    });
}

/// The courtyard with its stone floor a lit checkerboard and its plaster walls coloured by
/// their normals: custom materials beside glTF ones (textured, masked, blended).
fn custom_courtyard() -> Scene {
    let mut scene = courtyard();
    for m in &mut scene.materials {
        m.custom = match m.name.as_str() {
            "stone floor" => Some(CustomShading::new(
                "checker",
                &checker_params(
                    Vec3::new(0.8, 0.7, 0.5),
                    Vec3::new(0.2, 0.25, 0.3),
                    1.0,
                    0.0,
                ),
            )),
            "plaster" => Some(CustomShading::without_params("normal_colour")),
            _ => None,
        };
    }
    let named = scene
        .materials
        .iter()
        .filter(|m| m.custom.is_some())
        .count();
    assert_eq!(
        named, 2,
        "the courtyard's floor and walls are found by name"
    );
    scene
}

#[test]
fn every_path_equals_naive_with_material_programs_and_they_change_the_image() {
    let scene = custom_courtyard();
    let lights = procedural_lights(COURTYARD_LIGHT_REGION, 256, 7, 0.8, 2.6);
    let camera = renderer::frame::framing_camera(scene.bounds, 2.0);
    gpu_test(|gpu| {
        // MSAA 4 (single-sample frames of the programs: the test above). One renderer per scene,
        // switched from path to path in place (`reconfigure`: the scene stays uploaded).
        let msaa = 4;
        let config = |path| RendererConfig {
            width: WIDTH,
            height: HEIGHT,
            msaa,
            path,
            tile: 16,
            ..Default::default()
        };
        let mut custom = renderer(gpu, config(RenderPath::Naive), &scene);
        custom.set_lights(&lights).expect("lights fit");
        let mut frame = |path| {
            custom
                .reconfigure(config(path))
                .expect("the path suits the device");
            render_one_frame(gpu, &mut custom, &camera).rgba
        };
        let naive = frame(RenderPath::Naive);
        // The programs change the image: glTF's materials in their place differ a lot.
        let mut gltf = renderer(gpu, config(RenderPath::Naive), &courtyard());
        gltf.set_lights(&lights).expect("lights fit");
        let gltf = render_one_frame(gpu, &mut gltf, &camera).rgba;
        let (mean, _, _) = stats(&pixel_differences(&naive, &gltf, 3));
        assert!(
            mean > 5.0,
            "MSAA {msaa}: the material programs barely change the frame (mean {mean:.2})"
        );
        let prez = frame(RenderPath::NaivePrez);
        for (path, image) in [
            (RenderPath::NaivePrez, prez.clone()),
            (RenderPath::Tiled, frame(RenderPath::Tiled)),
            (RenderPath::Depth25, frame(RenderPath::Depth25)),
            (RenderPath::Clustered, frame(RenderPath::Clustered)),
        ] {
            let worst = largest_difference(&naive, &image);
            assert!(
                worst <= 1,
                "{path:?}, MSAA {msaa}: differs from naive by {worst}"
            );
        }
        // The deferred paths and the visibility buffer (one kernel a program, glTF's last), within
        // the TBDR tests' whole-image tolerances (`tbdr_gpu`).
        for path in [
            RenderPath::Tbdr,
            RenderPath::TbdrPerSample,
            RenderPath::Deferred,
            RenderPath::Visibility,
        ] {
            let (mean, p99, _) = stats(&pixel_differences(&prez, &frame(path), 3));
            eprintln!("{path:?}, MSAA {msaa}: mean {mean:.3}, 99th percentile {p99}");
            assert!(
                mean <= 0.3 && p99 <= 4,
                "{path:?}, MSAA {msaa}: differs from naive by mean {mean:.3}, 99th \
                 percentile {p99}"
            );
        }
    });
}

#[test]
fn bad_material_programs_and_bad_uses_are_typed_errors() {
    use shaders_gen::forward::{forward, prez};
    assert!(matches!(
        MaterialProgram::new(&forward::MODULE),
        Err(MaterialError::BuiltIn(_))
    ));
    assert!(matches!(
        MaterialProgram::new(&prez::MODULE),
        Err(MaterialError::MissingVariant { .. })
    ));
    let material = |custom: Option<CustomShading>, alpha_mode| Material {
        name: "custom".into(),
        custom,
        alpha_mode,
        ..Material::gltf_default()
    };
    let good = checker_params(Vec3::X, Vec3::Y, 1.0, 0.0);
    gpu_test(|gpu| {
        let mut r = Renderer::new(gpu, RendererConfig::default()).expect("renderer");
        let mut scene = slabs();
        // Not registered yet.
        let err = r.prepare_scene(&scene).expect_err("unregistered");
        assert!(
            matches!(err, RenderError::Input(InputError::Material(MaterialError::Unregistered { ref program, .. })) if program == "checker"),
            "{err}"
        );
        for p in programs() {
            r.register_material(p).expect("registers");
        }
        r.prepare_scene(&scene).expect("registered now");
        let wrong_size = CustomShading {
            program: "checker".into(),
            params: vec![0; 12],
        };
        let err = r
            .add_material(&material(Some(wrong_size), AlphaMode::Opaque))
            .expect_err("12 bytes are not a Checker");
        assert!(
            matches!(err, RenderError::Input(InputError::Material(MaterialError::ParamsSize { given: 12, expected, .. })) if expected == size_of::<checker::Checker>() as u64),
            "{err}"
        );
        let blended = material(Some(CustomShading::new("checker", &good)), AlphaMode::Blend);
        let err = r.add_material(&blended).expect_err("blended");
        assert!(
            matches!(
                err,
                RenderError::Input(InputError::Material(MaterialError::Blended { .. }))
            ),
            "{err}"
        );
        // A scene naming an unknown program is refused whole, and the previous scene stays.
        scene.materials[0].custom = Some(CustomShading::without_params("nowhere"));
        assert!(r.prepare_scene(&scene).is_err());
        let ok = material(
            Some(CustomShading::new("checker", &good)),
            AlphaMode::Opaque,
        );
        r.add_material(&ok)
            .expect("the previous scene takes a good material");
    });
}

/// A floor and three boxes of one mesh: `checkered` says which boxes draw with the checker
/// material; `shared` builds them as instances of one mesh (the renderer then gives them
/// their materials), else as a mesh per material.
fn boxes(checkered: [bool; 3], shared: bool) -> Scene {
    use renderer::scene::procedural::box_primitive;
    let mut b = SceneBuilder::new();
    let stone = b.material("stone", Vec3::new(0.6, 0.58, 0.55), 0.7);
    let checker = b.add_material(Material {
        name: "checker".into(),
        custom: Some(CustomShading::new(
            "checker",
            &checker_params(
                Vec3::new(0.9, 0.3, 0.2),
                Vec3::new(0.2, 0.3, 0.9),
                0.25,
                0.0,
            ),
        )),
        ..Material::gltf_default()
    });
    b.cuboid(Vec3::new(-4.0, -0.1, -3.0), Vec3::new(4.0, 0.0, 3.0), stone);
    let (lo, hi) = (Vec3::new(-0.6, 0.0, -0.6), Vec3::new(0.6, 1.2, 0.6));
    let plain = b.mesh("box", box_primitive(lo, hi, stone, false));
    let own = b.mesh("checker box", box_primitive(lo, hi, checker, false));
    for (i, &c) in checkered.iter().enumerate() {
        let at = glam::Mat4::from_translation(Vec3::new(-2.5 + 2.5 * i as f32, 0.0, 0.0));
        b.place(if c && !shared { own } else { plain }, at);
    }
    b.build()
}

#[test]
fn instances_of_one_mesh_choose_their_material() {
    let lights = |scene: &Scene| procedural_lights(scene.bounds, 16, 3, 1.5, 4.0);
    gpu_test(|gpu| {
        for path in [RenderPath::Naive, RenderPath::Clustered, RenderPath::Tbdr] {
            let config = RendererConfig {
                width: WIDTH,
                height: HEIGHT,
                path,
                msaa: 4,
                ..Default::default()
            };
            let shared = boxes([false; 3], true);
            let camera = renderer::frame::framing_camera(shared.bounds, 2.0);
            let frame_of = |scene: &Scene| {
                let mut r = renderer(gpu, config, scene);
                r.set_lights(&lights(scene)).expect("lights");
                render_one_frame(gpu, &mut r, &camera).rgba
            };
            let mut r = renderer(gpu, config, &shared);
            r.set_lights(&lights(&shared)).expect("lights");
            let plain = render_one_frame(gpu, &mut r, &camera).rgba;
            // The middle box (instance 2, after the floor) draws with the checker (material 1).
            let middle = r.scene_instance(2).expect("the middle box");
            r.set_instance_material(middle, 0, 1)
                .expect("a material of the scene");
            let given = render_one_frame(gpu, &mut r, &camera).rgba;
            let built = frame_of(&boxes([false, true, false], false));
            let worst = largest_difference(&given, &built);
            assert!(
                worst <= 1,
                "{path:?}: differs from the scene built so by {worst}"
            );
            assert!(
                largest_difference(&given, &plain) > 32,
                "{path:?}: the checker box does not show"
            );
            // The material cannot go while the instance draws with it; its own back, it can.
            let err = r.remove_material(1).expect_err("instance 2 draws with it");
            assert!(err.to_string().contains("instance 2"), "{err}");
            assert!(matches!(
                r.set_instance_material(middle, 1, 0),
                Err(RenderError::Input(InputError::NoSuchPrimitive {
                    primitive: 1,
                    count: 1
                }))
            ));
            r.set_instance_material(middle, 0, 0)
                .expect("back to stone");
            let back = render_one_frame(gpu, &mut r, &camera).rgba;
            assert!(
                largest_difference(&back, &plain) <= 1,
                "{path:?}: not back to stone"
            );
        }
    });
}
