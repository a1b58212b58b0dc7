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
    /// The file cannot be read, is not valid glTF, or its buffers or images fail to load.
    #[cfg(feature = "gltf")]
    #[error("{path}: cannot read or parse the glTF file: {source}")]
    Gltf {
        /// The scene file (`<memory>` for [`super::Scene::from_slice`]).
        path: PathBuf,
        /// What the gltf crate reported.
        #[source]
        source: gltf::Error,
    },
    /// The file lists an extension in `extensionsRequired` that the renderer does not
    /// implement.
    #[error(
        "{path}: requires extension `{extension}`, which this renderer does not support; \
         re-export the scene without it"
    )]
    UnsupportedExtension {
        /// The scene file.
        path: PathBuf,
        /// The extension's name.
        extension: String,
    },
    /// A drawn primitive lacks an attribute the renderer needs (`POSITION`).
    #[error("{path}: mesh `{mesh}` primitive {primitive} has no {attribute} attribute")]
    MissingAttribute {
        /// The scene file.
        path: PathBuf,
        /// The mesh's name (`#<index>` when it has none).
        mesh: String,
        /// The primitive's index in the mesh.
        primitive: usize,
        /// The glTF attribute name.
        attribute: &'static str,
    },
    /// A primitive's index buffer names a vertex past its last one.
    #[error(
        "{path}: mesh `{mesh}` primitive {primitive} uses vertex index {index}, but has only \
         {vertices} vertices"
    )]
    IndexOutOfRange {
        /// The scene file.
        path: PathBuf,
        /// The mesh's name (`#<index>` when it has none).
        mesh: String,
        /// The primitive's index in the mesh.
        primitive: usize,
        /// The first index out of range.
        index: u32,
        /// The primitive's vertex count.
        vertices: usize,
    },
    /// A vertex attribute or morph target of a primitive has a count other than its
    /// `POSITION` count.
    #[error("{path}: {what} has {got} values where {expected} are needed")]
    AttributeLength {
        /// The scene file.
        path: PathBuf,
        /// Which attribute of which primitive.
        what: String,
        /// Its count.
        got: usize,
        /// The primitive's `POSITION` count.
        expected: usize,
    },
    /// A node is reached twice walking the scene's node trees (a cycle, or two parents).
    #[error(
        "{path}: node {node} is reached twice (a cycle, or a node with two parents); glTF \
         requires the nodes to form trees"
    )]
    NodeHierarchy {
        /// The scene file.
        path: PathBuf,
        /// The index of the node reached twice.
        node: usize,
    },
    /// A buffer or image URI that is neither `data:` nor a readable regular file inside the
    /// scene's folder, or an external file named by a scene given as bytes.
    #[error("{path}: resource `{uri}` {reason}")]
    ExternalResource {
        /// The scene file.
        path: PathBuf,
        /// The URI (long ones cut).
        uri: String,
        /// Why it is refused, with what to do.
        reason: String,
    },
    /// An image or buffer of the scene exceeds a device limit
    /// ([`super::Scene::check_for_device`]).
    #[error("scene {what} is {value}, but this device allows at most {limit}; {advice}")]
    DeviceLimit {
        /// What is too large (an image's side, a buffer's bytes).
        what: String,
        /// Its size.
        value: u64,
        /// The device's limit for it.
        limit: u64,
        /// What to do, e.g. scale the image down or split the scene.
        advice: &'static str,
    },
    /// Malformed data the checks above do not name (a truncated GLB, a bad accessor, an index
    /// naming no mesh, material or image, ...); the message says what.
    #[error("scene is inconsistent: {0}")]
    Inconsistent(String),
}
