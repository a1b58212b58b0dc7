//! `EXT_mesh_gpu_instancing` and default morph weights. The Khronos models are checked
//! against their binary data read here at the byte offsets their JSON gives (quoted in the
//! comments) and against their READMEs; synthetic files against hand-computed values.

use glam::{Mat4, Quat, Vec3};
use renderer::scene::{Scene, SceneError};

use super::gltf_builder::{Bin, f32s_at, glb_bin, triangle};
use super::{check_consistent, workspace};

fn assert_near(got: Vec3, want: Vec3, what: &str) {
    assert!(
        got.abs_diff_eq(want, 1e-5),
        "{what}: got {got}, want {want}"
    );
}

/// SimpleInstancing.glb: one node, one unit cube (corners 0..1), 125 instances. Its JSON puts
/// TRANSLATION (125 float VEC3) at byte 720 of the binary chunk, ROTATION (125 float VEC4)
/// at 2220 and SCALE (125 float VEC3) at 4220.
#[test]
fn simple_instancing_places_one_cube_per_instance() {
    let path = workspace().join("tests/scenes/SimpleInstancing/SimpleInstancing.glb");
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    check_consistent(&scene);
    let bin = glb_bin(&path);
    let t = f32s_at(&bin, 720, 375);
    let r = f32s_at(&bin, 2220, 500);
    let s = f32s_at(&bin, 4220, 375);
    assert_eq!(scene.instances.len(), 125);
    let mut bounds = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for (i, instance) in scene.instances.iter().enumerate() {
        assert_eq!(instance.mesh, 0);
        let translation = Vec3::from_slice(&t[3 * i..]);
        let rotation = Quat::from_slice(&r[4 * i..]);
        let scale = Vec3::from_slice(&s[3 * i..]);
        for corner in 0..8 {
            let p = Vec3::new(
                (corner & 1) as f32,
                ((corner >> 1) & 1) as f32,
                ((corner >> 2) & 1) as f32,
            );
            // Scale, then rotate, then translate, as the extension orders them.
            let want = translation + rotation * (scale * p);
            assert_near(
                instance.world_from_mesh.transform_point3(p),
                want,
                &format!("instance {i} corner {corner}"),
            );
            bounds = (bounds.0.min(want), bounds.1.max(want));
        }
    }
    // The README: the first instance is the unmodified cube; the last is at (10, 10, 10),
    // scaled by 2 and turned about (1, 1, 1). Its README calls that 90° (per axis, as Euler
    // angles); the file's quaternion (0.5, 0.5, 0.5, 0.5) is the 120° turn that takes x to y,
    // y to z and z to x.
    assert!(
        scene.instances[0]
            .world_from_mesh
            .abs_diff_eq(Mat4::IDENTITY, 1e-6)
    );
    let last = scene.instances[124].world_from_mesh;
    assert_near(
        last.transform_point3(Vec3::ZERO),
        Vec3::splat(10.0),
        "last origin",
    );
    assert_near(
        last.transform_point3(Vec3::X),
        Vec3::new(10.0, 12.0, 10.0),
        "last x",
    );
    assert_near(
        last.transform_point3(Vec3::Y),
        Vec3::new(10.0, 10.0, 12.0),
        "last y",
    );
    assert_near(
        last.transform_point3(Vec3::Z),
        Vec3::new(12.0, 10.0, 10.0),
        "last z",
    );
    assert_near(scene.bounds.min, bounds.0, "bounds min");
    assert_near(scene.bounds.max, bounds.1, "bounds max");
}

/// A triangle on a node at (10, 0, 0) with `ext` as its `EXT_mesh_gpu_instancing`; view 1
/// holds 2 float VEC3 (1,0,0), (0,2,0); view 2 two i16 VEC4 (0,0,32767,0), (0,0,0,32767).
fn instanced(ext: &str, accessors: &str) -> Result<Scene, SceneError> {
    let mut bin = Bin::default();
    let pos = triangle(&mut bin);
    bin.f32s(&[1.0, 0.0, 0.0, 0.0, 2.0, 0.0]);
    let q: Vec<u8> = [0i16, 0, 32767, 0, 0, 0, 0, 32767]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    bin.view(&q);
    let required = r#"["EXT_mesh_gpu_instancing","KHR_texture_transform"]"#;
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"extensionsUsed":{required},"extensionsRequired":{required},
        {},"accessors":[{pos},{accessors}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
        "nodes":[{{"mesh":0,"translation":[10,0,0],"extensions":{{"EXT_mesh_gpu_instancing":{ext}}}}}],
        "scenes":[{{"nodes":[0]}}]}}"#,
        bin.json()
    );
    Scene::from_slice(&bin.glb(&json))
}

const TRANSLATIONS: &str = r#"{"bufferView":1,"componentType":5126,"count":2,"type":"VEC3"}"#;
const ROTATIONS_I16: &str =
    r#"{"bufferView":2,"componentType":5122,"normalized":true,"count":2,"type":"VEC4"}"#;

/// Normalized short rotations, no SCALE (identity), both extensions required: instance 0 is
/// a half turn about z then (1, 0, 0), instance 1 just (0, 2, 0); the node adds (10, 0, 0).
#[test]
fn instances_read_normalized_rotations_and_required_extensions_load() {
    let scene = instanced(
        r#"{"attributes":{"TRANSLATION":1,"ROTATION":2,"_ID":1}}"#,
        &format!("{TRANSLATIONS},{ROTATIONS_I16}"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.instances.len(), 2);
    let at = |i: usize, p: Vec3| scene.instances[i].world_from_mesh.transform_point3(p);
    assert_near(
        at(0, Vec3::X),
        Vec3::new(10.0, 0.0, 0.0),
        "instance 0, (1,0,0)",
    );
    assert_near(
        at(0, Vec3::Y),
        Vec3::new(11.0, -1.0, 0.0),
        "instance 0, (0,1,0)",
    );
    assert_near(
        at(1, Vec3::X),
        Vec3::new(11.0, 2.0, 0.0),
        "instance 1, (1,0,0)",
    );
    assert_near(scene.bounds.min, Vec3::new(10.0, -1.0, 0.0), "bounds min");
    assert_near(scene.bounds.max, Vec3::new(11.0, 3.0, 0.0), "bounds max");
}

#[test]
fn malformed_instancing_is_a_typed_error_naming_the_node() {
    let scale_1 = r#"{"bufferView":1,"componentType":5126,"count":1,"type":"VEC3"}"#;
    let vec2 = r#"{"bufferView":1,"componentType":5126,"count":2,"type":"VEC2"}"#;
    let raw_i16 = r#"{"bufferView":2,"componentType":5122,"count":2,"type":"VEC4"}"#;
    let past_view = r#"{"bufferView":1,"componentType":5126,"count":3,"type":"VEC3"}"#;
    let two = format!("{TRANSLATIONS},{scale_1}");
    for (ext, accessors, says) in [
        (
            r#"{"attributes":{"TRANSLATION":9}}"#,
            TRANSLATIONS,
            "accessor 9",
        ),
        (
            r#"{"attributes":{"TRANSLATION":"one"}}"#,
            TRANSLATIONS,
            "accessor \"one\"",
        ),
        (
            r#"{"attributes":{"TRANSLATION":1,"SCALE":2}}"#,
            two.as_str(),
            "same count",
        ),
        (r#"{"attributes":{"TRANSLATION":1}}"#, vec2, "float VEC3"),
        (
            r#"{"attributes":{"ROTATION":1}}"#,
            raw_i16,
            "normalized byte or short",
        ),
        (
            r#"{"attributes":{"TRANSLATION":1}}"#,
            past_view,
            "do not fit",
        ),
        (r#"{"attrs":{}}"#, TRANSLATIONS, "no `attributes`"),
    ] {
        match instanced(ext, accessors) {
            Err(e @ SceneError::Inconsistent(_)) => {
                let text = e.to_string();
                assert!(
                    text.contains("<memory>: node 0 EXT_mesh_gpu_instancing")
                        && text.contains(says),
                    "{ext}: {text}"
                );
            }
            other => panic!("{ext}: expected a typed error, got {other:?}"),
        }
    }
}

/// MorphPrimitivesTest.glb: `weights: [0.5]`. Primitive 0: POSITION (21 float VEC3) at byte
/// 396 of the binary chunk, its target's POSITION deltas at 816; primitive 1: 9 at 1224,
/// deltas at 1404. The deltas rise by up to 0.2 (their accessors' max), so half of that shows.
#[test]
fn morph_primitives_test_applies_its_default_weights() {
    let path = workspace().join("tests/scenes/MorphPrimitivesTest/MorphPrimitivesTest.glb");
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    check_consistent(&scene);
    let bin = glb_bin(&path);
    let primitives = &scene.meshes[0].primitives;
    assert_eq!(primitives.len(), 2);
    for (p, (base, delta, n)) in primitives.iter().zip([(396, 816, 21), (1224, 1404, 9)]) {
        let base = f32s_at(&bin, base, 3 * n);
        let delta = f32s_at(&bin, delta, 3 * n);
        assert_eq!(p.positions.len(), n);
        for (i, got) in p.positions.iter().enumerate() {
            let want = Vec3::from_slice(&base[3 * i..]) + 0.5 * Vec3::from_slice(&delta[3 * i..]);
            assert_near(*got, want, &format!("vertex {i}"));
        }
    }
    assert!(
        (scene.bounds.max.y - 0.1).abs() < 1e-6,
        "{:?}",
        scene.bounds
    );
    assert_eq!(scene.meshes.len(), 1, "no node has its own weights");
}

/// A triangle mesh with one morph target `target` (accessor 1, over view 1 = three float
/// deltas (0, 0, 1), view 2 = u16 index [2], view 3 = one float delta (0, 0, 2)),
/// `mesh_weights`, and nodes given as JSON.
fn morphed(target: &str, mesh_weights: &str, nodes: &str) -> Result<Scene, SceneError> {
    let mut bin = Bin::default();
    let pos = triangle(&mut bin);
    bin.f32s(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0]);
    bin.view(&[2, 0]);
    bin.f32s(&[0.0, 0.0, 2.0]);
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},{},"accessors":[{pos},{target}],
        "meshes":[{{"weights":{mesh_weights},"primitives":[{{"attributes":{{"POSITION":0}},"targets":[{{"POSITION":1}}]}}]}}],
        "nodes":{nodes},"scenes":[{{"nodes":[0]}}]}}"#,
        bin.json()
    );
    Scene::from_slice(&bin.glb(&json))
}

const DENSE: &str = r#"{"bufferView":1,"componentType":5126,"count":3,"type":"VEC3"}"#;
const SPARSE: &str = r#"{"componentType":5126,"count":3,"type":"VEC3","sparse":{"count":1,
    "indices":{"bufferView":2,"componentType":5123},"values":{"bufferView":3}}}"#;

/// Node 1's own weights draw a morphed copy of the mesh (appended); node 2's equal the mesh's
/// and share it.
#[test]
fn a_node_with_its_own_weights_gets_its_own_morphed_mesh() {
    let nodes = r#"[{"mesh":0,"children":[1,2,3]},{"mesh":0,"weights":[1.0]},{"mesh":0},
        {"mesh":0,"weights":[0.5]}]"#;
    let scene = morphed(DENSE, "[0.5]", nodes).unwrap_or_else(|e| panic!("{e}"));
    check_consistent(&scene);
    assert_eq!(scene.meshes.len(), 2);
    let meshes: Vec<usize> = scene.instances.iter().map(|i| i.mesh).collect();
    assert_eq!(meshes, [0, 1, 0, 0]);
    let z = |m: usize| {
        scene.meshes[m].primitives[0]
            .positions
            .iter()
            .map(|p| p.z)
            .collect::<Vec<_>>()
    };
    assert_eq!(z(0), [0.5; 3]);
    assert_eq!(z(1), [1.0; 3]);
    assert_eq!(scene.meshes[1].primitives[0].bounds.max.z, 1.0);
    assert_eq!(scene.bounds.max.z, 1.0);
}

/// A sparse target moves vertex 2 only, by 0.5 × (0, 0, 2); the generated flat normal follows
/// the morphed triangle (0,0,0), (1,0,0), (0,1,1): (0, −1, 1) / √2.
#[test]
fn sparse_targets_morph_and_generated_normals_follow() {
    let scene = morphed(SPARSE, "[0.5]", r#"[{"mesh":0}]"#).unwrap_or_else(|e| panic!("{e}"));
    check_consistent(&scene);
    let p = &scene.meshes[0].primitives[0];
    assert_eq!(p.positions, [Vec3::ZERO, Vec3::X, Vec3::new(0.0, 1.0, 1.0)]);
    for n in &p.normals {
        assert_near(*n, Vec3::new(0.0, -1.0, 1.0).normalize(), "normal");
    }
}

#[test]
fn malformed_morph_data_is_a_typed_error() {
    let vec2 = r#"{"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"}"#;
    let short = r#"{"bufferView":1,"componentType":5126,"count":2,"type":"VEC3"}"#;
    let node = r#"[{"mesh":0}]"#;
    for (target, weights, nodes, says) in [
        (DENSE, "[0.5, 0.5]", node, "2 weights for 1 morph targets"),
        (
            DENSE,
            "[0.5]",
            r#"[{"mesh":0,"weights":[1,1]}]"#,
            "2 weights for 1 morph targets",
        ),
        (vec2, "[0.5]", node, "must be float VEC3"),
        (short, "[0.5]", node, "2 values where 3 are needed"),
    ] {
        match morphed(target, weights, nodes) {
            Err(e) => {
                let text = e.to_string();
                assert!(
                    text.starts_with("<memory>") || text.contains("<memory>"),
                    "{text}"
                );
                assert!(text.contains(says), "{says}: {text}");
            }
            Ok(_) => panic!("{target} {weights} must not load"),
        }
    }
}
