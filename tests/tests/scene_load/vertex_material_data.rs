//! `COLOR_0` and `TEXCOORD_1`, texture samplers and `KHR_texture_transform` as the loader
//! reads them. Expected values are written out by hand from the glTF 2.0 specification and
//! the files' own data (the Khronos models' JSON, quoted in the comments), never computed
//! by the loader's code.

use glam::{Vec2, Vec4};
use renderer::scene::{
    Filter, Scene, SceneError, SceneWarning, TextureRef, TextureSampler, UvTransform, Wrap,
};

use super::gltf_builder::{Bin, png, triangle};
use super::{check_consistent, workspace};

fn load(relative: &str) -> Scene {
    let scene = Scene::load(workspace().join(relative)).unwrap_or_else(|e| panic!("{e}"));
    check_consistent(&scene);
    scene
}

fn base_ref(scene: &Scene, material: &str) -> TextureRef {
    let m = scene
        .materials
        .iter()
        .find(|m| m.name == material)
        .unwrap_or_else(|| panic!("no material {material}"));
    m.base_color_texture
        .unwrap_or_else(|| panic!("{material} has no base colour texture"))
}

fn assert_near4(got: &[Vec4], want: &[[f32; 4]]) {
    assert_eq!(got.len(), want.len());
    for (g, w) in got.iter().zip(want) {
        assert!(g.abs_diff_eq(Vec4::from(*w), 1e-6), "got {g}, want {w:?}");
    }
}

/// One triangle with `COLOR_0` as normalized u8 RGBA and `TEXCOORD_1` as normalized u16,
/// a second with float RGB colours (alpha 1) and float `TEXCOORD_1`, a third with u16 RGB.
#[test]
fn colors_and_second_uv_set_are_read_in_every_component_type() {
    let mut bin = Bin::default();
    let pos = triangle(&mut bin);
    bin.view(&[255, 0, 0, 255, 0, 51, 0, 102, 0, 0, 255, 0]);
    let uv16: Vec<u8> = [0u16, 65535, 32768, 0, 65535, 13107]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    bin.view(&uv16);
    bin.f32s(&[0.25, 0.5, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
    bin.f32s(&[0.5, 0.25, 2.0, -1.0, 0.0, 0.0]);
    let rgb16: Vec<u8> = [65535u16, 0, 0, 0, 65535, 0, 0, 0, 13107]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    bin.view(&rgb16);
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},{},"accessors":[{pos},
        {{"bufferView":1,"componentType":5121,"normalized":true,"count":3,"type":"VEC4"}},
        {{"bufferView":2,"componentType":5123,"normalized":true,"count":3,"type":"VEC2"}},
        {{"bufferView":3,"componentType":5126,"count":3,"type":"VEC3"}},
        {{"bufferView":4,"componentType":5126,"count":3,"type":"VEC2"}},
        {{"bufferView":5,"componentType":5123,"normalized":true,"count":3,"type":"VEC3"}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"COLOR_0":1,"TEXCOORD_1":2}}}},
          {{"attributes":{{"POSITION":0,"COLOR_0":3,"TEXCOORD_1":4}}}},
          {{"attributes":{{"POSITION":0,"COLOR_0":5}}}}]}}],
        "nodes":[{{"mesh":0}}],"scenes":[{{"nodes":[0]}}]}}"#,
        bin.json()
    );
    let scene = Scene::from_slice(&bin.glb(&json)).unwrap_or_else(|e| panic!("{e}"));
    check_consistent(&scene);
    let p = &scene.meshes[0].primitives;
    assert_near4(
        &p[0].colors,
        &[
            [1.0, 0.0, 0.0, 1.0],
            [0.0, 0.2, 0.0, 0.4],
            [0.0, 0.0, 1.0, 0.0],
        ],
    );
    let uvs1: Vec<Vec4> = p[0]
        .uvs1
        .iter()
        .map(|uv| uv.extend(0.0).extend(0.0))
        .collect();
    assert_near4(
        &uvs1,
        &[
            [0.0, 1.0, 0.0, 0.0],
            [32768.0 / 65535.0, 0.0, 0.0, 0.0],
            [1.0, 0.2, 0.0, 0.0],
        ],
    );
    assert_near4(
        &p[1].colors,
        &[
            [0.25, 0.5, 1.0, 1.0],
            [0.0, 0.0, 0.0, 1.0],
            [1.0, 1.0, 1.0, 1.0],
        ],
    );
    assert_eq!(
        p[1].uvs1,
        [Vec2::new(0.5, 0.25), Vec2::new(2.0, -1.0), Vec2::ZERO]
    );
    assert_near4(
        &p[2].colors,
        &[
            [1.0, 0.0, 0.0, 1.0],
            [0.0, 1.0, 0.0, 1.0],
            [0.0, 0.0, 0.2, 1.0],
        ],
    );
    assert!(p[2].uvs1.is_empty(), "no TEXCOORD_1: empty");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

/// A primitive with `attribute` given by an accessor `accessor` (JSON) over 2 floats' worth
/// of views, next to 3 positions.
fn with_attribute(attribute: &str, accessor: &str) -> Result<Scene, SceneError> {
    let mut bin = Bin::default();
    let pos = triangle(&mut bin);
    bin.f32s(&[0.5; 8]);
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},{},"accessors":[{pos},{accessor}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"{attribute}":1}}}}]}}],
        "nodes":[{{"mesh":0}}],"scenes":[{{"nodes":[0]}}]}}"#,
        bin.json()
    );
    Scene::from_slice(&bin.glb(&json))
}

#[test]
fn short_or_mistyped_color_and_uv1_streams_are_typed_errors() {
    for attribute in ["COLOR_0", "TEXCOORD_1"] {
        let short = r#"{"bufferView":1,"componentType":5126,"count":2,"type":"VEC2"}"#;
        let short = if attribute == "COLOR_0" {
            short.replace("VEC2", "VEC4")
        } else {
            short.to_owned()
        };
        match with_attribute(attribute, &short) {
            Err(SceneError::AttributeLength {
                what,
                got,
                expected,
                ..
            }) => {
                assert!(what.contains(attribute), "{what}");
                assert_eq!((got, expected), (2, 3));
            }
            other => panic!("{attribute}: expected a length error, got {other:?}"),
        }
        let mistyped = r#"{"bufferView":1,"componentType":5126,"count":3,"type":"SCALAR"}"#;
        match with_attribute(attribute, mistyped) {
            Err(e @ SceneError::Inconsistent(_)) => {
                assert!(e.to_string().contains("<memory>"), "{e}")
            }
            other => panic!("{attribute}: expected a type error, got {other:?}"),
        }
    }
}

/// TextureSettingsTest's samplers (its JSON): 1 `RepeatSClampTSampler`, 2
/// `RepeatTClampSSampler`, 3 `RepeatSMirrorTSampler`, 4 `RepeatTMirrorSSampler`; all with
/// magFilter LINEAR (9729) and minFilter NEAREST_MIPMAP_LINEAR (9986).
#[test]
fn texture_settings_test_samplers() {
    let scene = load("tests/scenes/TextureSettingsTest/TextureSettingsTest.glb");
    let sampler = |wrap_u, wrap_v| TextureSampler {
        wrap_u,
        wrap_v,
        mag_filter: Filter::Linear,
        min_filter: Filter::Nearest,
        mipmap_filter: Some(Filter::Linear),
    };
    for (material, wrap_u, wrap_v) in [
        ("TextureMirrorMaterialT", Wrap::Repeat, Wrap::MirroredRepeat),
        ("TextureMirrorMaterialS", Wrap::MirroredRepeat, Wrap::Repeat),
        ("TextureRepeatMaterialT", Wrap::ClampToEdge, Wrap::Repeat),
        ("TextureClampMaterialT", Wrap::Repeat, Wrap::ClampToEdge),
        ("TextureRepeatMaterialS", Wrap::Repeat, Wrap::ClampToEdge),
        ("TextureClampMaterialS", Wrap::ClampToEdge, Wrap::Repeat),
        ("LabelMaterial", Wrap::Repeat, Wrap::Repeat),
    ] {
        assert_eq!(
            base_ref(&scene, material).sampler,
            sampler(wrap_u, wrap_v),
            "{material}"
        );
    }
}

/// TextureCoordinateTest's one sampler is `{}`: repeat both ways, and the filters the file
/// leaves undefined are the renderer's choice, linear with linear mipmaps.
#[test]
fn texture_coordinate_test_sampler_has_the_defaults() {
    let scene = load("tests/scenes/TextureCoordinateTest/TextureCoordinateTest.glb");
    let want = TextureSampler {
        wrap_u: Wrap::Repeat,
        wrap_v: Wrap::Repeat,
        mag_filter: Filter::Linear,
        min_filter: Filter::Linear,
        mipmap_filter: Some(Filter::Linear),
    };
    for m in [
        "TopLeftMat",
        "TopRightMat",
        "BottomLeftMat",
        "BottomRightMat",
    ] {
        let t = base_ref(&scene, m);
        assert_eq!((t.sampler, t.tex_coord), (want, 0), "{m}");
        assert_eq!(t.transform, UvTransform::IDENTITY);
    }
}

/// TextureTransformTest's materials (its JSON) and their sampler (clamp, LINEAR both ways:
/// no mipmaps).
#[test]
fn texture_transform_test_transforms() {
    let scene = load("tests/scenes/TextureTransformTest/TextureTransformTest.gltf");
    let t = |offset: [f32; 2], rotation: f32, scale: [f32; 2]| UvTransform {
        offset: Vec2::from(offset),
        rotation,
        scale: Vec2::from(scale),
    };
    for (material, want) in [
        ("Offset U", t([0.5, 0.0], 0.0, [1.0, 1.0])),
        ("Offset V", t([0.0, 0.5], 0.0, [1.0, 1.0])),
        ("Offset UV", t([0.5, 0.5], 0.0, [1.0, 1.0])),
        (
            "Rotation",
            t([0.0, 0.0], std::f32::consts::FRAC_PI_8, [1.0, 1.0]),
        ),
        ("Scale", t([0.0, 0.0], 0.0, [1.5, 1.5])),
        ("All", t([-0.2, -0.1], 0.3, [1.5, 1.5])),
        ("Correct", UvTransform::IDENTITY),
    ] {
        assert_eq!(base_ref(&scene, material).transform, want, "{material}");
    }
    assert_eq!(
        base_ref(&scene, "All").sampler,
        TextureSampler {
            wrap_u: Wrap::ClampToEdge,
            wrap_v: Wrap::ClampToEdge,
            mag_filter: Filter::Linear,
            min_filter: Filter::Linear,
            mipmap_filter: None,
        }
    );
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

/// A material with all five textures, each through its own sampler and transform, on a
/// primitive with TEXCOORD_0 and TEXCOORD_1 (unless `with_uv1` is false).
fn five_textures(
    normal_transform: &str,
    with_uv1: bool,
    base_tex_coord: u32,
) -> Result<Scene, SceneError> {
    let mut bin = Bin::default();
    let pos = triangle(&mut bin);
    bin.f32s(&[0.0; 6]);
    let image = bin.view(&png());
    let uv1 = if with_uv1 { r#","TEXCOORD_1":1"# } else { "" };
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"extensionsUsed":["KHR_texture_transform"],{},
        "accessors":[{pos},{{"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"}}],
        "images":[{{"bufferView":{image},"mimeType":"image/png"}}],
        "samplers":[{{"minFilter":9728,"magFilter":9728}},{{"minFilter":9729,"wrapS":33648}},
          {{"minFilter":9984,"wrapT":33071}},{{"minFilter":9985}},{{"minFilter":9987,"magFilter":9729}}],
        "textures":[{{"source":0,"sampler":0}},{{"source":0,"sampler":1}},{{"source":0,"sampler":2}},
          {{"source":0,"sampler":3}},{{"source":0,"sampler":4}}],
        "materials":[{{"pbrMetallicRoughness":{{
            "baseColorTexture":{{"index":0,"texCoord":{base_tex_coord},"extensions":{{"KHR_texture_transform":{{"scale":[2,3],"texCoord":1}}}}}},
            "metallicRoughnessTexture":{{"index":1,"texCoord":1}}}},
          "normalTexture":{{"index":2,"extensions":{{"KHR_texture_transform":{normal_transform}}}}},
          "occlusionTexture":{{"index":3,"texCoord":1,"extensions":{{"KHR_texture_transform":{{"rotation":1.0,"texCoord":0}}}}}},
          "emissiveTexture":{{"index":4}}}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"TEXCOORD_0":1{uv1}}},"material":0}}]}}],
        "nodes":[{{"mesh":0}}],"scenes":[{{"nodes":[0]}}]}}"#,
        bin.json()
    );
    Scene::from_slice(&bin.glb(&json))
}

/// Every minFilter maps to a min filter and mipmap filter; each of the five texture slots
/// gets its texture's sampler and its own transform, whose `texCoord` overrides the
/// reference's (normal and occlusion transforms reach the loader as raw JSON).
#[test]
fn every_texture_slot_gets_its_sampler_and_transform() {
    let scene = five_textures(r#"{"offset":[0.25,0.5],"texCoord":1}"#, true, 0)
        .unwrap_or_else(|e| panic!("{e}"));
    let m = &scene.materials[0];
    let sampler = |wrap_u, wrap_v, mag_filter, min_filter, mipmap_filter| TextureSampler {
        wrap_u,
        wrap_v,
        mag_filter,
        min_filter,
        mipmap_filter,
    };
    use Filter::{Linear, Nearest};
    use Wrap::{ClampToEdge, MirroredRepeat, Repeat};
    let refs = [
        m.base_color_texture,
        m.metallic_roughness_texture,
        m.normal_texture,
        m.occlusion_texture,
        m.emissive_texture,
    ]
    .map(|t| t.expect("all five slots"));
    let want = [
        (sampler(Repeat, Repeat, Nearest, Nearest, None), 1),
        (sampler(MirroredRepeat, Repeat, Linear, Linear, None), 1),
        (
            sampler(Repeat, ClampToEdge, Linear, Nearest, Some(Nearest)),
            1,
        ),
        (sampler(Repeat, Repeat, Linear, Linear, Some(Nearest)), 0),
        (sampler(Repeat, Repeat, Linear, Linear, Some(Linear)), 0),
    ];
    for (i, (t, (s, set))) in refs.iter().zip(want).enumerate() {
        assert_eq!((t.sampler, t.tex_coord), (s, set), "slot {i}");
    }
    let transform = |offset: [f32; 2], rotation: f32, scale: [f32; 2]| UvTransform {
        offset: Vec2::from(offset),
        rotation,
        scale: Vec2::from(scale),
    };
    assert_eq!(refs[0].transform, transform([0.0, 0.0], 0.0, [2.0, 3.0]));
    assert_eq!(refs[1].transform, UvTransform::IDENTITY);
    assert_eq!(refs[2].transform, transform([0.25, 0.5], 0.0, [1.0, 1.0]));
    assert_eq!(refs[3].transform, transform([0.0, 0.0], 1.0, [1.0, 1.0]));
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

#[test]
fn a_malformed_raw_texture_transform_is_a_typed_error() {
    match five_textures(r#"{"offset":"left"}"#, true, 0) {
        Err(e @ SceneError::Inconsistent(_)) => {
            let text = e.to_string();
            assert!(
                text.contains("<memory>") && text.contains("KHR_texture_transform"),
                "{text}"
            );
        }
        other => panic!("expected a typed error, got {other:?}"),
    }
}

/// A material naming TEXCOORD_1 on a primitive without it (invalid glTF) loads with one
/// warning per set, samples TEXCOORD_0 there (uvs1 stays empty: the GPU side binds
/// TEXCOORD_0 in its place); a set past 1 becomes 0 with a warning.
#[test]
fn a_missing_or_unloaded_uv_set_falls_back_to_set_0_with_a_warning() {
    let scene = five_textures(r#"{"texCoord":1}"#, false, 0).unwrap_or_else(|e| panic!("{e}"));
    assert!(scene.meshes[0].primitives[0].uvs1.is_empty());
    assert_eq!(
        scene.warnings,
        [SceneWarning::MissingTexCoord {
            mesh: "#0".into(),
            primitive: 0,
            material: "#0".into(),
            set: 1
        }]
    );
    let scene = five_textures(r#"{"texCoord":3}"#, true, 0).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        scene.materials[0].normal_texture.map(|t| t.tex_coord),
        Some(0)
    );
    assert_eq!(
        scene.warnings,
        [SceneWarning::MissingTexCoord {
            mesh: "#0".into(),
            primitive: 0,
            material: "#0".into(),
            set: 3
        }]
    );
}
