//! What the loader checks in a glTF file around the gltf crate's own validation: the input
//! that crate would panic on or misread (found by the `gltf_load` fuzz target), and the
//! extensions the loader does not support (an error when required, a [`SceneWarning`] when
//! only used).

use std::path::Path;

use super::{SceneError, SceneWarning};

/// Extensions the loader implements: a file may require them, and using them draws no
/// warning. Every other extension is refused when required and named by a
/// [`SceneWarning::IgnoredExtension`] when only used.
const SUPPORTED: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_texture_transform",
    "EXT_mesh_gpu_instancing",
];

/// The document in `bytes`, validated by the gltf crate. gltf 1.4.1 refuses a required
/// extension it has no feature for (`EXT_mesh_gpu_instancing`, which the loader reads itself);
/// [`precheck`] has already refused every required extension outside [`SUPPORTED`], so the
/// required list is emptied before that validation.
pub(super) fn parse(bytes: &[u8]) -> Result<gltf::Gltf, gltf::Error> {
    let gltf::Gltf { document, blob } = gltf::Gltf::from_slice_without_validation(bytes)?;
    let mut root = document.into_json();
    root.extensions_required
        .retain(|e| !SUPPORTED.contains(&e.as_str()));
    Ok(gltf::Gltf {
        document: gltf::Document::from_json(root)?,
        blob,
    })
}

/// One warning per `extensionsUsed` entry outside [`SUPPORTED`], in the file's order (an
/// entry listed twice is named once), then one for animations and one for skins if the file
/// has any: what the file holds that the renderer ignores as a whole.
pub(super) fn unsupported_features(doc: &gltf::Document) -> Vec<SceneWarning> {
    let mut named: Vec<&str> = Vec::new();
    for e in doc.extensions_used() {
        if !SUPPORTED.contains(&e) && !named.contains(&e) {
            named.push(e);
        }
    }
    let mut warnings: Vec<SceneWarning> = named
        .into_iter()
        .map(|e| SceneWarning::IgnoredExtension(e.to_owned()))
        .collect();
    let animations = doc.animations().len();
    if animations > 0 {
        warnings.push(SceneWarning::AnimationsNotPlayed { count: animations });
    }
    let skins = doc.skins().len();
    if skins > 0 {
        warnings.push(SceneWarning::SkinsNotApplied { count: skins });
    }
    warnings
}

/// A GLB whose header declares a total length shorter than the 12-byte header itself: gltf
/// 1.4.1 subtracts the header size from it unchecked (`binary.rs:252`), which panics where
/// overflow checks are on and reads a wrapped length elsewhere (found by the `gltf_load` fuzz
/// target). Anything else about the header is left to gltf to report.
fn check_glb_header(bytes: &[u8], path: &Path) -> Result<(), SceneError> {
    const HEADER_BYTES: u32 = 12;
    let Some(declared) = bytes
        .strip_prefix(b"glTF")
        .and_then(|rest| rest.get(4..8))
        .and_then(|length| <[u8; 4]>::try_from(length).ok())
        .map(u32::from_le_bytes)
    else {
        return Ok(());
    };
    if declared < HEADER_BYTES {
        return Err(SceneError::Inconsistent(format!(
            "{}: the GLB header declares a total length of {declared} bytes, less than the \
             {HEADER_BYTES}-byte header itself; the file is truncated or not a GLB",
            path.display()
        )));
    }
    Ok(())
}

/// What must be checked before the gltf crate validates the document: an unsupported required
/// extension (named as such rather than as a generic validation failure); a POSITION accessor
/// index past the accessors, on which gltf-json 1.4.1's validation indexes out of bounds and
/// panics; and an image without a source or a buffer-view image without a MIME type, which
/// gltf 1.4.1 unwraps (both found by the `gltf_load` fuzz target). A document that does not parse is
/// left to gltf to report.
pub(super) fn precheck(bytes: &[u8], path: &Path) -> Result<(), SceneError> {
    check_glb_header(bytes, path)?;
    let json = if bytes.starts_with(b"glTF") {
        match gltf::binary::Glb::from_slice(bytes) {
            Ok(glb) => glb.json.into_owned(),
            Err(_) => return Ok(()),
        }
    } else {
        bytes.to_vec()
    };
    let Ok(root) = gltf::json::deserialize::from_slice::<gltf::json::Root>(&json) else {
        return Ok(());
    };
    if let Some(extension) = root
        .extensions_required
        .iter()
        .find(|e| !SUPPORTED.contains(&e.as_str()))
    {
        return Err(SceneError::UnsupportedExtension {
            path: path.to_path_buf(),
            extension: extension.clone(),
        });
    }
    // gltf 1.4.1's `Image::source` unwraps both of these.
    for (i, image) in root.images.iter().enumerate() {
        let problem = match (&image.buffer_view, &image.uri, &image.mime_type) {
            (Some(_), _, None) => "is stored in a buffer view but has no mimeType",
            (None, None, _) => "has neither a uri nor a bufferView",
            _ => continue,
        };
        return Err(SceneError::Inconsistent(format!(
            "{}: image {i} {problem}",
            path.display()
        )));
    }
    let position = gltf::json::validation::Checked::Valid(gltf::json::mesh::Semantic::Positions);
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            if let Some(index) = primitive.attributes.get(&position)
                && index.value() >= root.accessors.len()
            {
                return Err(SceneError::Inconsistent(format!(
                    "{}: mesh {m} primitive {p} reads POSITION from accessor {}, but the file \
                     has {} accessors",
                    path.display(),
                    index.value(),
                    root.accessors.len()
                )));
            }
        }
    }
    Ok(())
}

/// Accessor properties the gltf crate's reader asserts (debug builds) or silently misreads
/// (release builds) instead of reporting: a count of 0, a buffer-view stride smaller than one
/// element, and an attribute of the wrong type for what the loader reads. Found by the
/// `gltf_load` fuzz target. Attributes are checked on the meshes the scene draws (`used`,
/// by mesh index): the others are never read.
pub(super) fn check_accessors(
    doc: &gltf::Document,
    used: &[bool],
    path: &Path,
) -> Result<(), SceneError> {
    use gltf::accessor::{DataType, Dimensions};
    let bad = |what: String| {
        Err(SceneError::Inconsistent(format!(
            "{}: {what}",
            path.display()
        )))
    };
    for a in doc.accessors() {
        let i = a.index();
        if a.count() == 0 {
            return bad(format!(
                "accessor {i} has count 0 (glTF requires at least 1)"
            ));
        }
        if let Some(stride) = a.view().and_then(|v| v.stride())
            && stride < a.size()
        {
            return bad(format!(
                "accessor {i}'s buffer view has a byte stride of {stride}, less than its {}-byte \
                 elements",
                a.size()
            ));
        }
        if a.sparse().is_some_and(|s| s.count() == 0) {
            return bad(format!("accessor {i} is sparse with count 0"));
        }
    }
    for mesh in doc
        .meshes()
        .filter(|m| used.get(m.index()).copied().unwrap_or(false))
    {
        for p in mesh.primitives() {
            for (semantic, a) in p.attributes() {
                let ok = match semantic {
                    gltf::Semantic::Positions | gltf::Semantic::Normals => {
                        a.dimensions() == Dimensions::Vec3 && a.data_type() == DataType::F32
                    }
                    gltf::Semantic::Tangents => {
                        a.dimensions() == Dimensions::Vec4 && a.data_type() == DataType::F32
                    }
                    gltf::Semantic::TexCoords(_) => {
                        a.dimensions() == Dimensions::Vec2
                            && matches!(a.data_type(), DataType::F32 | DataType::U8 | DataType::U16)
                    }
                    gltf::Semantic::Colors(_) => {
                        matches!(a.dimensions(), Dimensions::Vec3 | Dimensions::Vec4)
                            && matches!(a.data_type(), DataType::F32 | DataType::U8 | DataType::U16)
                    }
                    _ => true,
                };
                if !ok {
                    return bad(format!(
                        "mesh {} primitive {} has {semantic:?} as {:?} {:?}, which glTF does not \
                         allow",
                        mesh.index(),
                        p.index(),
                        a.dimensions(),
                        a.data_type()
                    ));
                }
            }
            if let Some(a) = p.indices()
                && !(a.dimensions() == Dimensions::Scalar
                    && matches!(a.data_type(), DataType::U8 | DataType::U16 | DataType::U32))
            {
                return bad(format!(
                    "mesh {} primitive {} has indices as {:?} {:?}; glTF requires unsigned \
                     scalars",
                    mesh.index(),
                    p.index(),
                    a.dimensions(),
                    a.data_type()
                ));
            }
        }
    }
    Ok(())
}
