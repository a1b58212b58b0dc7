//! What a scene file holds that the renderer loads but does not draw as the file says: each
//! is reported once, as a [`SceneWarning`] in [`super::Scene::warnings`], never dropped in
//! silence. Tools print them when they open a scene.

/// Something in a valid file that the renderer skips or approximates, naming what and where.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SceneWarning {
    /// An extension in `extensionsUsed` that the renderer does not implement: whatever it
    /// adds is ignored (the core glTF data still draws).
    #[error("extension `{0}` is not supported; what it adds is ignored")]
    IgnoredExtension(String),
    /// A primitive of a drawn mesh whose mode is points or lines (`POINTS`, `LINES`,
    /// `LINE_LOOP`, `LINE_STRIP`): it is not drawn. Triangle strips and fans are drawn (as
    /// lists) and draw no warning.
    #[error(
        "mesh `{mesh}` primitive {primitive} is {mode}, which this renderer does not draw; it is \
         skipped"
    )]
    SkippedPrimitive {
        /// The mesh's name (`#<index>` when it has none).
        mesh: String,
        /// The primitive's index in the file's mesh.
        primitive: usize,
        /// The mode as glTF names it.
        mode: &'static str,
    },
    /// A mesh that no node of the loaded scene uses: it is not read at all (whatever it holds
    /// cannot refuse the file), and stays in [`super::Scene::meshes`] with no primitives so
    /// mesh indices stay the file's.
    #[error("mesh `{mesh}` is used by no node of the scene; it is skipped")]
    UnusedMesh {
        /// The mesh's name (`#<index>` when it has none).
        mesh: String,
    },
    /// A material samples `TEXCOORD_<set>` (set 1 and up) on a primitive that lacks it, which
    /// glTF forbids ("a mesh primitive must have the corresponding texture coordinate
    /// attributes"): drawing beats refusing, so those textures sample `TEXCOORD_0` there.
    #[error(
        "mesh `{mesh}` primitive {primitive} has no TEXCOORD_{set}, which its material \
         `{material}` samples; TEXCOORD_0 is used instead"
    )]
    MissingTexCoord {
        /// The mesh's name (`#<index>` when it has none).
        mesh: String,
        /// The primitive's index in the file's mesh.
        primitive: usize,
        /// The material's name (`#<index>` when it has none).
        material: String,
        /// The missing UV set.
        set: u32,
    },
    /// A material samples `TEXCOORD_<set>` with set 2 or more, which the renderer does not
    /// load: those textures sample `TEXCOORD_0` instead (reported per material).
    #[error(
        "material `{material}` samples TEXCOORD_{set}; only TEXCOORD_0 and TEXCOORD_1 are \
         loaded, so TEXCOORD_0 is used instead"
    )]
    UnsupportedTexCoord {
        /// The material's name (`#<index>` when it has none).
        material: String,
        /// The UV set it samples (2 or more).
        set: u32,
    },
    /// The file has animations, which the renderer does not play: nodes stay at their
    /// transforms in the file, morph targets at their default weights.
    #[error(
        "{count} animation(s) are not played; the scene draws at the file's node transforms and \
         default morph weights"
    )]
    AnimationsNotPlayed {
        /// How many animations the file has.
        count: usize,
    },
    /// The file has skins, which the renderer does not apply: a skinned mesh draws its vertices
    /// as stored (its bind pose) at its node's transform.
    #[error(
        "{count} skin(s) are not applied; skinned meshes draw in their bind pose at their node's \
         transform"
    )]
    SkinsNotApplied {
        /// How many skins the file has.
        count: usize,
    },
}
