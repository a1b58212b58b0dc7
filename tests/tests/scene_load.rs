//! glTF scene loading: the committed scene, the shared real scenes, and malformed files that
//! must each give a typed error naming the file and the problem.

use std::path::{Path, PathBuf};

use renderer::scene::{AlphaMode, LightKind, Scene, SceneError};

/// Synthetic GLB files for the modules below.
#[path = "scene_load/gltf_builder.rs"]
mod gltf_builder;
/// `EXT_mesh_gpu_instancing` and default morph weights.
#[path = "scene_load/instancing_morph.rs"]
mod instancing_morph;
/// Image formats, primitive modes, unused meshes and ignored extensions.
#[path = "scene_load/modes_formats.rs"]
mod modes_formats;
/// `COLOR_0`, `TEXCOORD_1`, samplers and `KHR_texture_transform`.
#[path = "scene_load/vertex_material_data.rs"]
mod vertex_material_data;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn committed_scene() -> PathBuf {
    workspace().join("tests/scenes/AlphaBlendModeTest/AlphaBlendModeTest.glb")
}

/// A shared scene; a missing file fails the test loudly (it is never a pass).
fn shared_scene(relative: &str) -> Scene {
    let path = workspace().join("../shared/scenes").join(relative);
    assert!(
        path.is_file(),
        "shared scene {} is missing: these tests need ../shared/scenes",
        path.display()
    );
    Scene::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn check_consistent(scene: &Scene) {
    for mesh in &scene.meshes {
        for p in &mesh.primitives {
            let n = p.positions.len();
            assert!(n > 0 && p.indices.len() % 3 == 0);
            assert_eq!(
                (p.normals.len(), p.uvs.len(), p.tangents.len()),
                (n, n, n),
                "{}",
                mesh.name
            );
            assert!(p.indices.iter().all(|&i| (i as usize) < n));
            assert!(
                p.tangents
                    .iter()
                    .all(|t| t.is_finite() && (t.w == 1.0 || t.w == -1.0))
            );
            if let Some(m) = p.material {
                assert!(m < scene.materials.len());
            }
        }
    }
    for m in &scene.materials {
        for t in [
            m.base_color_texture,
            m.normal_texture,
            m.metallic_roughness_texture,
            m.occlusion_texture,
            m.emissive_texture,
        ]
        .into_iter()
        .flatten()
        {
            let image = &scene.images[t.image];
            assert_eq!(image.rgba8.len(), (image.width * image.height * 4) as usize);
        }
    }
    assert!(!scene.bounds.is_empty());
}

#[test]
fn committed_scene_loads_with_all_alpha_modes() {
    let scene = Scene::load(committed_scene()).unwrap_or_else(|e| panic!("{e}"));
    check_consistent(&scene);
    let modes: Vec<AlphaMode> = scene.materials.iter().map(|m| m.alpha_mode).collect();
    assert!(modes.contains(&AlphaMode::Opaque));
    assert!(modes.contains(&AlphaMode::Blend));
    assert!(
        modes
            .iter()
            .any(|m| matches!(m, AlphaMode::Mask { cutoff } if *cutoff > 0.0 && *cutoff < 1.0))
    );
    assert!(scene.triangle_count() > 0);
}

#[test]
fn damaged_helmet_has_every_texture_kind() {
    let scene = shared_scene("DamagedHelmet/glTF-Binary/DamagedHelmet.glb");
    check_consistent(&scene);
    let m = &scene.materials[0];
    assert!(m.base_color_texture.is_some() && m.normal_texture.is_some());
    assert!(
        m.metallic_roughness_texture.is_some()
            && m.occlusion_texture.is_some()
            && m.emissive_texture.is_some()
    );
    assert!(scene.triangle_count() > 10_000);
}

#[test]
fn lights_punctual_lamp_has_infinite_range_point_lights() {
    let scene = shared_scene("LightsPunctualLamp/glTF/LightsPunctualLamp.gltf");
    check_consistent(&scene);
    let points: Vec<_> = scene
        .lights
        .iter()
        .filter(|l| l.kind == LightKind::Point)
        .collect();
    assert_eq!(points.len(), 5);
    assert!(
        points.iter().all(|l| l.range.is_none()),
        "no range set: infinite"
    );
    assert!(
        scene
            .materials
            .iter()
            .any(|m| m.alpha_mode == AlphaMode::Blend)
    );
}

#[test]
fn stained_glass_lamp_and_alpha_blend_test_load() {
    let lamp = shared_scene("StainedGlassLamp/glTF-JPG-PNG/StainedGlassLamp.gltf");
    check_consistent(&lamp);
    assert!(lamp.triangle_count() > 30_000);
    check_consistent(&shared_scene(
        "AlphaBlendModeTest/glTF-Binary/AlphaBlendModeTest.glb",
    ));
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("scene-load-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn load_err(path: &Path) -> SceneError {
    match Scene::load(path) {
        Ok(_) => panic!("{} must not load", path.display()),
        Err(e) => {
            assert!(
                e.to_string().contains(&path.display().to_string()),
                "the error names the file: {e}"
            );
            e
        }
    }
}

#[test]
fn truncated_and_garbled_files_are_errors() {
    let dir = temp_dir("broken");
    let bytes = std::fs::read(committed_scene()).expect("committed scene");
    let truncated = dir.join("truncated.glb");
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).expect("write");
    assert!(matches!(load_err(&truncated), SceneError::Gltf { .. }));
    let garbled = dir.join("garbled.gltf");
    std::fs::write(&garbled, b"{ \"asset\": { \"version\": ").expect("write");
    assert!(matches!(load_err(&garbled), SceneError::Gltf { .. }));
    assert!(matches!(
        load_err(&dir.join("missing.gltf")),
        SceneError::Gltf { .. }
    ));
}

/// A one-triangle glTF whose index buffer holds `indices` and which requires `required`.
fn write_triangle(dir: &Path, indices: [u16; 3], required: &[&str]) -> PathBuf {
    let mut bin = Vec::new();
    for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        for c in p {
            bin.extend_from_slice(&c.to_le_bytes());
        }
    }
    for i in indices {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    bin.extend_from_slice(&[0, 0]);
    std::fs::write(dir.join("tri.bin"), &bin).expect("write bin");
    let required: Vec<String> = required.iter().map(|r| format!("\"{r}\"")).collect();
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"extensionsUsed":[{r}],"extensionsRequired":[{r}],
        "buffers":[{{"uri":"tri.bin","byteLength":{len}}}],
        "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":6}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
                     {{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1}}]}}],
        "nodes":[{{"mesh":0}}],"scenes":[{{"nodes":[0]}}],"scene":0}}"#,
        r = required.join(","),
        len = bin.len()
    );
    let path = dir.join("tri.gltf");
    std::fs::write(&path, json).expect("write gltf");
    path
}

#[test]
fn a_valid_minimal_triangle_loads_and_gets_normals_and_tangents() {
    let scene = Scene::load(write_triangle(&temp_dir("ok"), [0, 1, 2], &[]))
        .unwrap_or_else(|e| panic!("{e}"));
    check_consistent(&scene);
    assert_eq!(scene.triangle_count(), 1);
    assert_eq!(
        scene.meshes[0].primitives[0].normals[0],
        glam::Vec3::Z,
        "flat normal generated"
    );
}

#[test]
fn out_of_range_indices_are_an_error() {
    let path = write_triangle(&temp_dir("oob"), [0, 1, 7], &[]);
    match load_err(&path) {
        SceneError::IndexOutOfRange {
            index, vertices, ..
        } => assert_eq!((index, vertices), (7, 3)),
        e => panic!("wrong error: {e}"),
    }
}

#[test]
fn an_unsupported_required_extension_is_named() {
    let path = write_triangle(&temp_dir("ext"), [0, 1, 2], &["KHR_draco_mesh_compression"]);
    match load_err(&path) {
        SceneError::UnsupportedExtension { extension, .. } => {
            assert_eq!(extension, "KHR_draco_mesh_compression")
        }
        e => panic!("wrong error: {e}"),
    }
}

#[test]
fn committed_scene_uploads_with_exact_buffers() {
    use renderer::scene::GpuScene;
    let scene = Scene::load(committed_scene()).unwrap_or_else(|e| panic!("{e}"));
    tests::gpu::gpu_test(|gpu| {
        let uploaded = GpuScene::upload(gpu.device(), &scene);
        assert_eq!(uploaded.meshes.len(), scene.meshes.len());
        let read = |b: &wgpu::Buffer| {
            renderer::readback::read_buffer::<u8>(gpu.device(), gpu.queue(), b).expect("readback")
        };
        let g = &uploaded.geometry;
        let streams = [
            read(&g.positions),
            read(&g.normals),
            read(&g.uvs),
            read(&g.uvs1),
            read(&g.colors),
            read(&g.tangents),
        ];
        let indices = read(&g.indices);
        // Every primitive's vertices at its base vertex in each shared stream, its indices at
        // its first index; no TEXCOORD_1 reads TEXCOORD_0, no COLOR_0 reads white.
        for (m, mesh) in scene.meshes.iter().enumerate() {
            for (k, p) in mesh.primitives.iter().enumerate() {
                let placed = &uploaded.meshes[m][k];
                assert_eq!(placed.index_count as usize, p.indices.len());
                let first = placed.first_index as usize * 4;
                assert_eq!(
                    &indices[first..first + p.indices.len() * 4],
                    bytemuck::cast_slice::<_, u8>(&p.indices)
                );
                let white = vec![glam::Vec4::ONE; p.positions.len()];
                let expected: [&[u8]; 6] = [
                    bytemuck::cast_slice(&p.positions),
                    bytemuck::cast_slice(&p.normals),
                    bytemuck::cast_slice(&p.uvs),
                    bytemuck::cast_slice(if p.uvs1.is_empty() { &p.uvs } else { &p.uvs1 }),
                    bytemuck::cast_slice(if p.colors.is_empty() {
                        &white
                    } else {
                        &p.colors
                    }),
                    bytemuck::cast_slice(&p.tangents),
                ];
                for (stream, want) in streams.iter().zip(expected) {
                    let stride = want.len() / p.positions.len().max(1);
                    let at = placed.base_vertex as usize * stride;
                    assert_eq!(&stream[at..at + want.len()], want, "mesh {m} primitive {k}");
                }
            }
        }
    });
}
