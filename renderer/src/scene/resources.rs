//! Which external resources a glTF file may name. A scene is untrusted input: a buffer or image
//! URI may only be a `data:` URI or a relative path to a regular file inside the scene's folder,
//! so a file cannot make the loader read `/dev/zero`, another user's files or a URL.

use std::path::{Component, Path, PathBuf};

use super::SceneError;

/// Checks every buffer and image URI of `doc` against the policy above. `base` is the scene's
/// folder (`None` for a scene given as bytes, which may name no external file).
pub(super) fn check_uris(
    doc: &gltf::Document,
    base: Option<&Path>,
    path: &Path,
) -> Result<(), SceneError> {
    let buffers = doc.buffers().filter_map(|b| match b.source() {
        gltf::buffer::Source::Uri(uri) => Some(uri),
        gltf::buffer::Source::Bin => None,
    });
    let images = doc.images().filter_map(|i| match i.source() {
        gltf::image::Source::Uri { uri, .. } => Some(uri),
        gltf::image::Source::View { .. } => None,
    });
    for uri in buffers.chain(images) {
        if let Err(reason) = check_uri(uri, base) {
            return Err(SceneError::ExternalResource {
                path: path.to_path_buf(),
                uri: shorten(uri),
                reason,
            });
        }
    }
    Ok(())
}

fn check_uri(uri: &str, base: Option<&Path>) -> Result<(), String> {
    if uri.starts_with("data:") {
        return Ok(());
    }
    if uri.contains(':') {
        return Err(
            "uses a URI scheme other than `data:`; only files beside the scene and \
                    embedded data are read"
                .into(),
        );
    }
    let decoded = percent_decode(uri)
        .ok_or("is not valid percent-encoded UTF-8; write the file name plainly")?;
    let Some(base) = base else {
        return Err(
            "names an external file, but the scene was given as bytes; embed the data \
                    (GLB or a `data:` URI) or load the scene from its file"
                .into(),
        );
    };
    let relative = PathBuf::from(&decoded);
    if !relative
        .components()
        .all(|c| matches!(c, Component::Normal(_) | Component::CurDir))
    {
        return Err(
            "leaves the scene's folder (absolute, or through `..`); keep the file in \
                    the scene's folder or below it"
                .into(),
        );
    }
    let full = base.join(&relative);
    match std::fs::metadata(&full) {
        Ok(m) if m.is_file() => Ok(()),
        Ok(_) => Err(format!(
            "names {}, which is not a regular file",
            full.display()
        )),
        Err(e) => Err(format!(
            "names {}, which cannot be read: {e}",
            full.display()
        )),
    }
}

/// `%XX` decoding as glTF URIs use it; `None` for a malformed escape or invalid UTF-8.
fn percent_decode(uri: &str) -> Option<String> {
    let mut out = Vec::with_capacity(uri.len());
    let mut bytes = uri.bytes();
    while let Some(b) = bytes.next() {
        if b == b'%' {
            let hex = [bytes.next()?, bytes.next()?];
            let hex = std::str::from_utf8(&hex).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
        } else {
            out.push(b);
        }
    }
    String::from_utf8(out).ok()
}

/// A URI as an error message shows it: long `data:` payloads and names are cut.
fn shorten(uri: &str) -> String {
    const MAX: usize = 80;
    match uri.char_indices().nth(MAX) {
        Some((cut, _)) => format!("{}…", &uri[..cut]),
        None => uri.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_data_and_files_inside_the_folder_pass() {
        let dir = std::env::temp_dir().join("renderer-uri-policy");
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        std::fs::write(dir.join("sub/a b.bin"), b"x").unwrap();
        assert!(check_uri("data:application/octet-stream;base64,AAAA", None).is_ok());
        assert!(check_uri("sub/a%20b.bin", Some(&dir)).is_ok());
        assert!(check_uri("./sub/a b.bin", Some(&dir)).is_ok());
        for bad in [
            "../secret.bin",
            "sub/../../secret.bin",
            "/dev/zero",
            "file:///dev/zero",
            "https://example.com/a.bin",
            "%2e%2e/secret.bin",
            "%ff.bin",
            "%4",
            "sub",
            "missing.bin",
        ] {
            assert!(check_uri(bad, Some(&dir)).is_err(), "{bad} passed");
        }
        assert!(check_uri("sub/a%20b.bin", None).is_err());
    }

    #[test]
    fn long_uris_are_cut_in_messages() {
        let long = format!("data:{}", "A".repeat(10_000));
        assert_eq!(shorten(&long).chars().count(), 81);
        assert_eq!(shorten("a.bin"), "a.bin");
    }
}
