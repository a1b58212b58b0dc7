//! "No hand-written source file over 500 lines": the size at which a file stops being read as
//! one thing. Tests live in their own files to stay under it. The exceptions are listed with
//! their reason, so a new long file fails the check instead of joining a silent list.

/// The most lines a hand-written `.rs` file may have.
pub const MAX_LINES: usize = 500;

/// Files allowed past [`MAX_LINES`], each with the reason it cannot be split yet.
pub const LONG_FILE_EXCEPTIONS: &[(&str, &str)] = &[(
    "shaders_gen/src/deferred/tiled_shading.rs",
    "one #[shader] module (TBDR shading, G-buffer capture, light volumes) whose helpers call four \
     DSL libraries; a library may not use another library, so the helpers cannot move out \
     without changing the generated shaders",
)];

/// The folders of a crate whose `.rs` files are hand-written sources.
pub const SOURCE_FOLDERS: &[&str] = &["src", "tests", "benches", "examples", "fuzz_targets"];

/// Every file of `files` (workspace-relative path, text) over [`MAX_LINES`] lines that is not
/// an exception, with its line count.
pub fn long_files(files: &[(String, String)]) -> Vec<(String, usize)> {
    files
        .iter()
        .filter(|(path, _)| !LONG_FILE_EXCEPTIONS.iter().any(|(p, _)| p == path))
        .map(|(path, text)| (path.clone(), text.lines().count()))
        .filter(|&(_, lines)| lines > MAX_LINES)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(path: &str, lines: usize) -> (String, String) {
        (path.to_owned(), "x\n".repeat(lines))
    }

    #[test]
    fn a_file_over_the_limit_fails_and_one_at_it_passes() {
        let long = long_files(&[file("a/src/long.rs", 501), file("a/src/ok.rs", 500)]);
        assert_eq!(long, [("a/src/long.rs".to_owned(), 501)]);
    }

    #[test]
    fn listed_exceptions_pass() {
        let (path, _) = LONG_FILE_EXCEPTIONS[0];
        assert!(long_files(&[file(path, 900)]).is_empty());
    }
}
