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
}
