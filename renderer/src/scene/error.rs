//! Why a scene file could not be loaded: malformed data, a required extension the renderer
//! does not implement, an external resource outside the scene's folder, or a scene too large
//! for the device. What a valid file holds that the renderer does not draw (points and lines,
//! meshes no node uses, extensions only listed in `extensionsUsed`) is never an error: it is a
//! [`super::SceneWarning`]. Every pixel format the gltf crate decodes converts to RGBA8, and
//! triangle strips and fans convert to lists.

use std::path::PathBuf;

/// A scene file that cannot be used, naming the file and the problem.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    #[error("{path}: cannot read or parse the glTF file: {source}")]
    Gltf {
        path: PathBuf,
        #[source]
        source: gltf::Error,
    },
    #[error(
        "{path}: requires extension `{extension}`, which this renderer does not support; \
         re-export the scene without it"
    )]
    UnsupportedExtension { path: PathBuf, extension: String },
    #[error("{path}: mesh `{mesh}` primitive {primitive} has no {attribute} attribute")]
    MissingAttribute {
        path: PathBuf,
        mesh: String,
        primitive: usize,
        attribute: &'static str,
    },
    #[error(
        "{path}: mesh `{mesh}` primitive {primitive} uses vertex index {index}, but has only \
         {vertices} vertices"
    )]
    IndexOutOfRange {
        path: PathBuf,
        mesh: String,
        primitive: usize,
        index: u32,
        vertices: usize,
    },
    #[error("{path}: {what} has {got} values where {expected} are needed")]
    AttributeLength {
        path: PathBuf,
        what: String,
        got: usize,
        expected: usize,
    },
    #[error(
        "{path}: node {node} is reached twice (a cycle, or a node with two parents); glTF \
         requires the nodes to form trees"
    )]
    NodeHierarchy { path: PathBuf, node: usize },
    #[error("{path}: resource `{uri}` {reason}")]
    ExternalResource {
        path: PathBuf,
        uri: String,
        reason: String,
    },
    #[error("scene {what} is {value}, but this device allows at most {limit}; {advice}")]
    DeviceLimit {
        what: String,
        value: u64,
        limit: u64,
        advice: &'static str,
    },
    #[error("scene is inconsistent: {0}")]
    Inconsistent(String),
}
