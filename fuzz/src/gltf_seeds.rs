//! The starting corpus of the `gltf_load` target: small self-contained scenes that exercise
//! every part of the loader (node trees, cameras, every light kind, materials with textures,
//! indexed and unindexed primitives, missing normals, GLB and `.gltf`, strips, fans, points, an
//! unused mesh and an ignored extension), the malformed inputs of
//! the scene-loading tests (truncated, garbled, an index out of range, an unsupported required
//! extension), and the shared scene whose buffer is small enough to embed (LightsPunctualLamp,
//! its images replaced by 1×1 PNGs so one execution stays fast).

use std::path::Path;

use serde_json::{Value, json};

/// A 1×1 RGBA PNG as a `data:` URI.
fn pixel_png() -> String {
    let mut png = Vec::new();
    let image = image::RgbaImage::from_pixel(1, 1, image::Rgba([200, 120, 40, 255]));
    // Encoding a 1×1 image into memory cannot fail; an empty URI would only make a seed invalid.
    let _ = image.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png);
    format!("data:image/png;base64,{}", base64::encode(png))
}

fn data_uri(bytes: &[u8]) -> String {
    format!(
        "data:application/octet-stream;base64,{}",
        base64::encode(bytes)
    )
}

/// One triangle (positions, normals, UVs, u16 indices) in one buffer.
fn triangle_bin(indices: [u16; 3]) -> Vec<u8> {
    let mut bin = Vec::new();
    for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        bin.extend(p.iter().flat_map(|f| f.to_le_bytes()));
    }
    for _ in 0..3 {
        bin.extend([0.0f32, 0.0, 1.0].iter().flat_map(|f| f.to_le_bytes()));
    }
    for uv in [[0.0f32, 0.0], [1.0, 0.0], [0.0, 1.0]] {
        bin.extend(uv.iter().flat_map(|f| f.to_le_bytes()));
    }
    bin.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    bin.extend([0, 0]);
    bin
}

/// The JSON of a triangle scene; `uri` is the buffer's URI (`None`: the GLB BIN chunk).
fn triangle_json(uri: Option<String>, len: usize, required: &[&str], normals: bool) -> Value {
    let mut attributes = json!({ "POSITION": 0, "TEXCOORD_0": 2 });
    if normals {
        attributes["NORMAL"] = json!(1);
    }
    let mut buffer = json!({ "byteLength": len });
    if let Some(uri) = uri {
        buffer["uri"] = json!(uri);
    }
    json!({
        "asset": { "version": "2.0" },
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensionsRequired": required,
        "scene": 0,
        "scenes": [{ "nodes": [0, 3] }],
        "nodes": [
            { "children": [1, 2], "translation": [0.0, 0.5, 0.0] },
            { "mesh": 0, "scale": [2.0, 2.0, 2.0] },
            { "camera": 0, "translation": [0.0, 0.0, 3.0] },
            { "extensions": { "KHR_lights_punctual": { "light": 0 } }, "children": [4, 5] },
            { "extensions": { "KHR_lights_punctual": { "light": 1 } },
              "rotation": [0.0, 0.6, 0.0, 0.8] },
            { "extensions": { "KHR_lights_punctual": { "light": 2 } } }
        ],
        "cameras": [{ "type": "perspective",
                      "perspective": { "yfov": 0.8, "znear": 0.1, "zfar": 100.0 } }],
        "extensions": { "KHR_lights_punctual": { "lights": [
            { "type": "point", "intensity": 10.0, "color": [1.0, 0.5, 0.2] },
            { "type": "spot", "intensity": 5.0, "range": 4.0,
              "spot": { "innerConeAngle": 0.2, "outerConeAngle": 0.6 } },
            { "type": "directional", "intensity": 2.0 }
        ] } },
        "meshes": [{ "primitives": [
            { "attributes": attributes.clone(), "indices": 3, "material": 0 },
            { "attributes": attributes, "material": 1 }
        ] }],
        "materials": [
            { "pbrMetallicRoughness": { "baseColorTexture": { "index": 0 },
                                        "metallicFactor": 0.5 },
              "normalTexture": { "index": 0, "scale": 0.5 },
              "emissiveFactor": [1.0, 0.0, 0.0], "alphaMode": "MASK", "alphaCutoff": 0.3 },
            { "alphaMode": "BLEND", "doubleSided": true }
        ],
        "textures": [{ "source": 0 }],
        "images": [{ "uri": pixel_png() }],
        "buffers": [buffer],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": 36 },
            { "buffer": 0, "byteOffset": 36, "byteLength": 36 },
            { "buffer": 0, "byteOffset": 72, "byteLength": 24 },
            { "buffer": 0, "byteOffset": 96, "byteLength": 6 }
        ],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
              "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0] },
            { "bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3" },
            { "bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2" },
            { "bufferView": 3, "componentType": 5123, "count": 3, "type": "SCALAR" }
        ]
    })
}

fn gltf_text(indices: [u16; 3], required: &[&str], normals: bool) -> Vec<u8> {
    let bin = triangle_bin(indices);
    let doc = triangle_json(Some(data_uri(&bin)), bin.len(), required, normals);
    doc.to_string().into_bytes()
}

fn glb(indices: [u16; 3]) -> Vec<u8> {
    let bin = triangle_bin(indices);
    let doc = triangle_json(None, bin.len(), &[], true);
    let glb = gltf::binary::Glb {
        header: gltf::binary::Header {
            magic: *b"glTF",
            version: 2,
            length: 0,
        },
        json: doc.to_string().into_bytes().into(),
        bin: Some(bin.into()),
    };
    glb.to_vec().unwrap_or_default()
}

/// The triangle scene with a strip, a fan and a POINTS primitive added to its mesh, a second
/// mesh (LINES) that no node uses, and an extension the renderer ignores in `extensionsUsed`.
fn modes_and_unused_mesh() -> Vec<u8> {
    let bin = triangle_bin([0, 1, 2]);
    let mut doc = triangle_json(Some(data_uri(&bin)), bin.len(), &[], true);
    let primitive = |mode: u32| json!({ "attributes": { "POSITION": 0 }, "mode": mode });
    if let Some(p) = doc["meshes"][0]["primitives"].as_array_mut() {
        p.extend([primitive(5), primitive(6), primitive(0)]);
    }
    if let Some(m) = doc["meshes"].as_array_mut() {
        m.push(json!({ "primitives": [primitive(1)] }));
    }
    if let Some(e) = doc["extensionsUsed"].as_array_mut() {
        e.push(json!("KHR_materials_clearcoat"));
    }
    doc.to_string().into_bytes()
}

/// LightsPunctualLamp with its buffer embedded and every image a 1×1 PNG, when the shared
/// scenes are present.
fn lamp() -> Option<Vec<u8>> {
    let dir =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/scenes/LightsPunctualLamp/glTF");
    let text = std::fs::read(dir.join("LightsPunctualLamp.gltf")).ok()?;
    let mut doc: Value = serde_json::from_slice(&text).ok()?;
    for buffer in doc.get_mut("buffers")?.as_array_mut()? {
        let uri = buffer.get("uri")?.as_str()?.to_owned();
        buffer["uri"] = json!(data_uri(&std::fs::read(dir.join(uri)).ok()?));
    }
    let pixel = pixel_png();
    for image in doc.get_mut("images")?.as_array_mut()? {
        image["uri"] = json!(pixel);
        if let Some(image) = image.as_object_mut() {
            image.remove("mimeType");
        }
    }
    Some(doc.to_string().into_bytes())
}

/// Every seed, by name.
pub fn seeds() -> Vec<(String, Vec<u8>)> {
    let valid = gltf_text([0, 1, 2], &[], true);
    let mut seeds = vec![
        ("triangle.gltf", valid.clone()),
        ("triangle.glb", glb([0, 1, 2])),
        ("triangle-modes-unused-mesh.gltf", modes_and_unused_mesh()),
        (
            "triangle-flat-normals.gltf",
            gltf_text([0, 1, 2], &[], false),
        ),
        ("index-out-of-range.gltf", gltf_text([0, 1, 7], &[], true)),
        (
            "unsupported-extension.gltf",
            gltf_text([0, 1, 2], &["KHR_draco_mesh_compression"], true),
        ),
        ("truncated.gltf", valid[..valid.len() / 2].to_vec()),
        ("garbled.gltf", b"{ \"asset\": { \"version\": ".to_vec()),
    ];
    if let Some(lamp) = lamp() {
        seeds.push(("lights-punctual-lamp.gltf", lamp));
    }
    seeds.into_iter().map(|(n, b)| (n.to_owned(), b)).collect()
}
