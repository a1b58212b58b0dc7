//! The scratch workspace that `bench-codegen`'s incremental-rebuild measurement edits, so that it
//! never writes to the checkout: a copy of `shaders_gen` (its manifest and sources) under
//! `target/bench/codegen-workspace/`, in a workspace of its own. Its root manifest is the
//! checkout's with `members` narrowed to the copy and every other path dependency (`codegen`,
//! `shader-dsl`) pointing back at the checkout's crates, and the checkout's `Cargo.lock` comes
//! along: the same versions, features, profiles and lints as the real build. A run killed
//! mid-build (Ctrl-C) leaves only a stale copy, which the next run replaces.

use std::path::{Path, PathBuf};

use anyhow::{Context as _, Result, bail, ensure};

/// Where the scratch workspace lives, relative to the workspace root.
pub(super) const SCRATCH_DIR: &str = "target/bench/codegen-workspace";
/// The crate copied into it (its folder, relative to the workspace root).
const COPIED: &str = "shaders_gen";

/// A scratch workspace holding a copy of `shaders_gen`; removed when dropped.
#[derive(Debug)]
pub(super) struct Scratch {
    dir: PathBuf,
}

impl Scratch {
    /// Copies `shaders_gen` of the workspace at `root` into a fresh workspace at `dir` (whatever
    /// was at `dir` is removed first).
    pub(super) fn create(root: &Path, dir: &Path) -> Result<Scratch> {
        if dir.exists() {
            std::fs::remove_dir_all(dir)
                .with_context(|| format!("removing the old scratch copy {}", dir.display()))?;
        }
        let scratch = Scratch {
            dir: dir.to_path_buf(),
        };
        copy_dir(
            &root.join(COPIED).join("src"),
            &dir.join(COPIED).join("src"),
        )?;
        copy_file(
            &root.join(COPIED).join("Cargo.toml"),
            &dir.join(COPIED).join("Cargo.toml"),
        )?;
        copy_file(&root.join("Cargo.lock"), &dir.join("Cargo.lock"))?;
        let manifest_path = root.join("Cargo.toml");
        let manifest = std::fs::read_to_string(&manifest_path)
            .with_context(|| format!("reading {}", manifest_path.display()))?;
        let scratch_manifest = scratch_manifest(&manifest, root)?;
        std::fs::write(dir.join("Cargo.toml"), scratch_manifest)
            .with_context(|| format!("writing {}", dir.join("Cargo.toml").display()))?;
        Ok(scratch)
    }

    /// The scratch workspace's folder.
    pub(super) fn dir(&self) -> &Path {
        &self.dir
    }

    /// The copy of `file`, a path relative to the workspace root inside the copied crate.
    pub(super) fn copy_of(&self, file: &str) -> Result<PathBuf> {
        ensure!(
            Path::new(file).starts_with(COPIED),
            "{file} is not in the copied crate {COPIED}"
        );
        Ok(self.dir.join(file))
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        // Best effort: a copy left behind is under target/ and replaced by the next run.
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

fn copy_file(from: &Path, to: &Path) -> Result<()> {
    if let Some(dir) = to.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    std::fs::copy(from, to)
        .map(drop)
        .with_context(|| format!("copying {} to {}", from.display(), to.display()))
}

fn copy_dir(from: &Path, to: &Path) -> Result<()> {
    std::fs::create_dir_all(to).with_context(|| format!("creating {}", to.display()))?;
    for entry in std::fs::read_dir(from).with_context(|| format!("reading {}", from.display()))? {
        let path = entry?.path();
        let target = to.join(path.file_name().context("a file without a name")?);
        if path.is_dir() {
            copy_dir(&path, &target)?;
        } else {
            copy_file(&path, &target)?;
        }
    }
    Ok(())
}

/// The scratch workspace's root manifest, from the checkout's (`manifest`, at `root`): in
/// `[workspace]`, `members` becomes the copied crate alone (and `default-members` and `exclude`
/// go); in `[workspace.dependencies]`, a path dependency other than the copied crate points at
/// the checkout's folder. Everything else (versions, features, lints, profiles) is kept as is.
pub(super) fn scratch_manifest(manifest: &str, root: &Path) -> Result<String> {
    let mut out = String::with_capacity(manifest.len() + 256);
    let mut section = String::new();
    let mut skipping_array = false;
    let mut members = 0;
    for line in manifest.lines() {
        let trimmed = line.trim();
        if skipping_array {
            skipping_array = !trimmed.contains(']');
            continue;
        }
        if trimmed.starts_with('[') {
            section = trimmed.to_owned();
        }
        let key = trimmed.split('=').next().unwrap_or_default().trim();
        if section == "[workspace]" && ["members", "default-members", "exclude"].contains(&key) {
            // A multi-line array: drop its lines up to the closing bracket.
            skipping_array = !trimmed.contains(']');
            if key == "members" {
                out.push_str(&format!("members = [\"{COPIED}\"]\n"));
                members += 1;
            }
            continue;
        }
        if section == "[workspace.dependencies]" {
            out.push_str(&with_absolute_path(line, root));
        } else {
            out.push_str(line);
        }
        out.push('\n');
    }
    if members != 1 {
        bail!("the workspace manifest has {members} `members` lists in [workspace], not one");
    }
    Ok(out)
}

/// `line` with its `path = "dir"` made absolute under `root`, unless `dir` is the copied crate
/// (which the scratch workspace has).
fn with_absolute_path(line: &str, root: &Path) -> String {
    const KEY: &str = "path = \"";
    let Some(start) = line.find(KEY).map(|i| i + KEY.len()) else {
        return line.to_owned();
    };
    let Some(len) = line[start..].find('"') else {
        return line.to_owned();
    };
    let dir = &line[start..start + len];
    if dir == COPIED || Path::new(dir).is_absolute() {
        return line.to_owned();
    }
    let absolute = root.join(dir).display().to_string().replace('\\', "/");
    format!("{}{absolute}{}", &line[..start], &line[start + len..])
}
