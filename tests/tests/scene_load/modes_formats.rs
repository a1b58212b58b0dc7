//! What a valid glTF file may hold that the loader once refused: 16-bit and grey+alpha PNG
//! textures (converted to RGBA8), triangle strips and fans (converted to triangle lists with
//! glTF's winding), point and line primitives (skipped with a warning each), meshes no node of
//! the scene uses (skipped unread, with a warning), and extensions listed in `extensionsUsed`
//! that the renderer ignores (one warning each). Expected values are written out by hand from
//! the glTF 2.0 specification and the PNG data, never computed by the loader's code.

use std::io::Cursor;

use renderer::scene::{Scene, SceneWarning};

use super::gltf_builder::glb;
use super::{check_consistent, workspace};

fn png(image: image::DynamicImage) -> Vec<u8> {
    let mut bytes = Vec::new();
    image
        .write_to(&mut Cursor::new(&mut bytes), image::ImageFormat::Png)
        .expect("encode PNG");
    bytes
}

fn load(bytes: &[u8]) -> Scene {
    Scene::from_slice(bytes).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn sixteen_bit_and_grey_alpha_pngs_become_rgba8() {
    use image::{DynamicImage, ImageBuffer, LumaA, Rgb, Rgba};
    // 16-bit channels become round(v / 257): 25828 / 257 = 100.498, 25829 / 257 = 100.502.
    let rgb16 =
        ImageBuffer::<Rgb<u16>, _>::from_raw(2, 1, vec![0, 25828, 65535, 25829, 257, 32896])
            .expect("2x1");
    let grey_alpha16 =
        ImageBuffer::<LumaA<u16>, _>::from_raw(2, 1, vec![65535, 0, 25829, 32896]).expect("2x1");
    let grey16 = ImageBuffer::<image::Luma<u16>, _>::from_raw(1, 1, vec![514]).expect("1x1");
    let rgba16 =
        ImageBuffer::<Rgba<u16>, _>::from_raw(1, 1, vec![2570, 5140, 7710, 10280]).expect("1x1");
    let grey_alpha8 = ImageBuffer::<LumaA<u8>, _>::from_raw(1, 1, vec![7, 200]).expect("1x1");
    let pngs = [
        png(DynamicImage::ImageRgb16(rgb16)),
        png(DynamicImage::ImageLumaA16(grey_alpha16)),
        png(DynamicImage::ImageLuma16(grey16)),
        png(DynamicImage::ImageRgba16(rgba16)),
        png(DynamicImage::ImageLumaA8(grey_alpha8)),
    ];
    let mut bin = Vec::new();
    let mut views = Vec::new();
    let mut images = Vec::new();
    for (i, p) in pngs.iter().enumerate() {
        views.push(format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
            bin.len(),
            p.len()
        ));
        images.push(format!(r#"{{"bufferView":{i},"mimeType":"image/png"}}"#));
        bin.extend_from_slice(p);
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
    }
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"buffers":[{{"byteLength":{}}}],"bufferViews":[{}],"images":[{}]}}"#,
        bin.len(),
        views.join(","),
        images.join(",")
    );
    let scene = load(&glb(&json, &bin));
    let texels: Vec<&[u8]> = scene.images.iter().map(|i| i.rgba8.as_slice()).collect();
    assert_eq!(
        texels,
        [
            &[0, 100, 255, 255, 101, 1, 128, 255][..],
            &[255, 255, 255, 0, 101, 101, 101, 128],
            &[2, 2, 2, 255],
            &[10, 20, 30, 40],
            &[7, 7, 7, 200],
        ]
    );
    assert_eq!(
        scene
            .images
            .iter()
            .map(|i| (i.width, i.height))
            .collect::<Vec<_>>(),
        [(2, 1), (2, 1), (1, 1), (1, 1), (1, 1)]
    );
}

#[test]
fn strips_and_fans_become_lists_and_points_and_lines_are_skipped() {
    let path = workspace().join("tests/scenes/MeshPrimitiveModes/MeshPrimitiveModes.gltf");
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    check_consistent(&scene);
    let skipped = |mesh: &str, mode| SceneWarning::SkippedPrimitive {
        mesh: mesh.into(),
        primitive: 0,
        mode,
    };
    assert_eq!(
        scene.warnings,
        [
            skipped("mesh with POINTS", "POINTS"),
            skipped("mesh with LINES", "LINES"),
            skipped("mesh with LINE_LOOP", "LINE_LOOP"),
            skipped("mesh with LINE_STRIP", "LINE_STRIP"),
        ]
    );
    assert_eq!(
        scene.warnings[1].to_string(),
        "mesh `mesh with LINES` primitive 0 is LINES, which this renderer does not draw; \
         it is skipped"
    );
    for m in &scene.meshes[..4] {
        assert!(m.primitives.is_empty(), "{} is skipped", m.name);
    }
    let indices = |m: usize| scene.meshes[m].primitives[0].indices.clone();
    assert_eq!(
        indices(4),
        [0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5, 0, 5, 6, 0, 6, 1]
    );
    // Strip [2, 3, 1, 4, 6, 5]: triangle i is {v_i, v_(i+1+i%2), v_(i+2-i%2)}.
    assert_eq!(indices(5), [2, 3, 1, 3, 4, 1, 1, 4, 6, 4, 5, 6]);
    // Fan [0, 1, 2, 3, 4, 5, 6, 1]: triangle i is {v_(i+1), v_(i+2), v_0}.
    assert_eq!(
        indices(6),
        [1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5, 0, 5, 6, 0, 6, 1, 0]
    );
    // The hexagon lies in z = 0 and every triangle faces +Z (counter-clockwise seen from +Z),
    // so the generated flat normals of the vertices they use are all +Z.
    for m in 4..7 {
        let p = &scene.meshes[m].primitives[0];
        for tri in p.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| p.positions[tri[k] as usize]);
            assert!((b - a).cross(c - a).z > 0.0, "mesh {m} triangle {tri:?}");
        }
        for &i in &p.indices {
            let n = p.normals[i as usize];
            assert!(
                n.abs_diff_eq(glam::Vec3::Z, 1e-6),
                "mesh {m} vertex {i}: {n}"
            );
        }
    }
    assert_eq!(scene.triangle_count(), 6 + 4 + 6);
    assert_eq!(scene.instances.len(), 7);
}

/// Four corners of the unit square in z = 0 (48 bytes), then u16 indices [0, 1, 2, 0, 1, 9]
/// (12 bytes): the last three name a vertex that does not exist.
fn square_bin() -> Vec<u8> {
    let mut bin = Vec::new();
    for p in [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ] {
        bin.extend(p.iter().flat_map(|c| c.to_le_bytes()));
    }
    bin.extend([0u16, 1, 2, 0, 1, 9].iter().flat_map(|i| i.to_le_bytes()));
    bin
}

/// Accessors: 0 = the four corners, 1 = the first two corners, 2 = indices [0, 1, 2],
/// 3 = indices [0, 1, 9].
const SQUARE_ACCESSORS: &str = r#""buffers":[{"byteLength":60}],
  "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":12}],
  "accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
    {"bufferView":0,"componentType":5126,"count":2,"type":"VEC3","min":[0,0,0],"max":[1,0,0]},
    {"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"},
    {"bufferView":1,"byteOffset":6,"componentType":5123,"count":3,"type":"SCALAR"}]"#;

#[test]
fn unindexed_strips_and_fans_convert_and_too_short_ones_draw_nothing() {
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},{SQUARE_ACCESSORS},
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"mode":5}},
                                  {{"attributes":{{"POSITION":1}},"mode":5}},
                                  {{"attributes":{{"POSITION":0}},"mode":6}},
                                  {{"attributes":{{"POSITION":1}},"mode":6}}]}}],
        "nodes":[{{"mesh":0}}],"scenes":[{{"nodes":[0]}}],"scene":0}}"#
    );
    let scene = load(&glb(&json, &square_bin()));
    check_consistent(&scene);
    assert_eq!(scene.warnings, []);
    let lists: Vec<&[u32]> = scene.meshes[0]
        .primitives
        .iter()
        .map(|p| p.indices.as_slice())
        .collect();
    // The two-vertex strip and fan have no triangle: they are dropped.
    assert_eq!(lists, [&[0, 1, 2, 1, 3, 2][..], &[1, 2, 0, 2, 3, 0]]);
}

#[test]
fn a_mesh_no_node_of_the_scene_uses_is_skipped_unread() {
    // Mesh 1 holds points and a triangle with an out-of-range index and a NORMAL of scalar
    // integers (each refuses the file when read); only node 1, outside the scene, names it.
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},{SQUARE_ACCESSORS},
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":2}}]}},
                  {{"name":"loose points","primitives":[{{"attributes":{{"POSITION":0}},"indices":2,"mode":0}},
                                                       {{"attributes":{{"POSITION":0,"NORMAL":2}},"indices":3}}]}}],
        "nodes":[{{"mesh":0}},{{"mesh":1}}],"scenes":[{{"nodes":[0]}}],"scene":0}}"#
    );
    let scene = load(&glb(&json, &square_bin()));
    check_consistent(&scene);
    assert_eq!(
        scene.warnings,
        [SceneWarning::UnusedMesh {
            mesh: "loose points".into()
        }]
    );
    assert_eq!(
        scene.warnings[0].to_string(),
        "mesh `loose points` is used by no node of the scene; it is skipped"
    );
    assert_eq!(scene.meshes.len(), 2, "mesh indices stay those of the file");
    assert!(scene.meshes[1].primitives.is_empty());
    assert_eq!(scene.meshes[0].primitives[0].indices, [0, 1, 2]);
    assert_eq!(scene.instances.len(), 1);
    assert_eq!(scene.triangle_count(), 1);
    scene
        .check_for_device(&wgpu::Limits::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(renderer::frame_data::draw_plan(&scene).len(), 1);
}

#[test]
fn each_ignored_used_extension_is_named_once_and_supported_ones_may_be_required() {
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},{SQUARE_ACCESSORS},
        "extensionsUsed":["KHR_materials_clearcoat","KHR_texture_transform","KHR_lights_punctual",
            "EXT_mesh_gpu_instancing","KHR_materials_emissive_strength","KHR_xmp","KHR_xmp"],
        "extensionsRequired":["KHR_texture_transform","EXT_mesh_gpu_instancing"],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":2}}]}}],
        "nodes":[{{"mesh":0}}],"scenes":[{{"nodes":[0]}}],"scene":0}}"#
    );
    let scene = load(&glb(&json, &square_bin()));
    assert_eq!(
        scene.warnings,
        [
            SceneWarning::IgnoredExtension("KHR_materials_clearcoat".into()),
            SceneWarning::IgnoredExtension("KHR_xmp".into()),
        ]
    );
    assert_eq!(
        scene.warnings[1].to_string(),
        "extension `KHR_xmp` is not supported; what it adds is ignored"
    );
    assert_eq!(scene.triangle_count(), 1);
}

/// Animations and skins are not played or applied: a file that has them loads in its static
/// pose, with one warning for each (counted from the file's JSON, not through the loader).
#[test]
fn animations_and_skins_are_named_once_each() {
    let path = workspace().join("tests/scenes/SimpleSkin/SimpleSkin.gltf");
    let json: String = std::fs::read_to_string(&path).expect("SimpleSkin is committed");
    let count = |key: &str| -> usize {
        let start = json
            .find(&format!("\"{key}\""))
            .expect("the key is in the file");
        let body = &json[start..];
        let open = body.find('[').expect("an array");
        let mut depth = 0usize;
        let mut items = 0usize;
        for c in body[open..].chars() {
            match c {
                '[' | '{' => {
                    if depth == 1 && c == '{' {
                        items += 1;
                    }
                    depth += 1;
                }
                ']' | '}' => {
                    depth -= 1;
                    if depth == 0 {
                        break;
                    }
                }
                _ => {}
            }
        }
        items
    };
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        scene.warnings,
        [
            SceneWarning::AnimationsNotPlayed {
                count: count("animations")
            },
            SceneWarning::SkinsNotApplied {
                count: count("skins")
            },
        ]
    );
    assert!(scene.triangle_count() > 0, "the skinned mesh still draws");
}
