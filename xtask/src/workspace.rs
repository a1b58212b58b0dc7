//! Where the workspace is, for commands that read or write files in it. Its own file so that the
//! commands use it without importing `main.rs`, which calls them (no import circle).

/// The workspace root: the parent of this crate's manifest directory when it exists (a build
/// run in place), else the current directory (a binary carried to another machine and run from
/// a checkout's root).
pub(crate) fn workspace_root() -> std::path::PathBuf {
    let manifest_dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    match manifest_dir.parent() {
        Some(root) if root.join("Cargo.toml").is_file() => root.to_path_buf(),
        _ => std::env::current_dir().unwrap_or_else(|_| manifest_dir.to_path_buf()),
    }
}
